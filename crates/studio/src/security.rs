//! Who may talk to the studio: requests must name the session's token in
//! their path, carry a `Host` header naming the address the server listens
//! on (a page on another site that rebinds its DNS name to 127.0.0.1 sends
//! its own name), and, when they carry an `Origin`, that same address.

use axum::http::{header, HeaderMap};
use rand::RngCore;
use std::net::SocketAddr;

/// A new unguessable token: 128 random bits from the operating system, in
/// hex.
pub fn new_token() -> String {
    let mut bytes = [0u8; 16];
    rand::rngs::OsRng.fill_bytes(&mut bytes);
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// Compare a token in time independent of where it first differs.
pub fn token_matches(given: &str, token: &str) -> bool {
    given.len() == token.len()
        && given
            .bytes()
            .zip(token.bytes())
            .fold(0u8, |acc, (a, b)| acc | (a ^ b))
            == 0
}

/// The `Host` values a request may carry for a server at `addr`.
pub fn allowed_hosts(addr: SocketAddr) -> Vec<String> {
    let port = addr.port();
    let mut hosts = vec![format!("{addr}")];
    if addr.ip().is_loopback() {
        hosts.push(format!("localhost:{port}"));
        hosts.push(format!("127.0.0.1:{port}"));
        hosts.push(format!("[::1]:{port}"));
    }
    hosts.sort();
    hosts.dedup();
    hosts
}

/// Why a request is refused, or `None` when its `Host` and `Origin` are
/// the server's own.
pub fn refusal(headers: &HeaderMap, hosts: &[String]) -> Option<&'static str> {
    let host = headers.get(header::HOST).and_then(|v| v.to_str().ok());
    match host {
        Some(host) if hosts.iter().any(|h| h.eq_ignore_ascii_case(host)) => {}
        _ => return Some("the Host header does not name this server"),
    }
    if let Some(origin) = headers.get(header::ORIGIN) {
        let origin = origin.to_str().unwrap_or("");
        let own = origin
            .strip_prefix("http://")
            .is_some_and(|rest| hosts.iter().any(|h| h.eq_ignore_ascii_case(rest)));
        if !own {
            return Some("the page comes from another origin");
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use axum::http::HeaderValue;

    fn headers(host: &str, origin: Option<&str>) -> HeaderMap {
        let mut map = HeaderMap::new();
        map.insert(header::HOST, HeaderValue::from_str(host).unwrap());
        if let Some(origin) = origin {
            map.insert(header::ORIGIN, HeaderValue::from_str(origin).unwrap());
        }
        map
    }

    #[test]
    fn only_the_servers_own_host_and_origin_pass() {
        let hosts = allowed_hosts("127.0.0.1:7171".parse().unwrap());
        assert_eq!(refusal(&headers("127.0.0.1:7171", None), &hosts), None);
        assert_eq!(
            refusal(
                &headers("localhost:7171", Some("http://localhost:7171")),
                &hosts
            ),
            None
        );
        assert!(refusal(&headers("evil.example:7171", None), &hosts).is_some());
        assert!(refusal(&headers("localhost:7172", None), &hosts).is_some());
        assert!(refusal(
            &headers("127.0.0.1:7171", Some("http://evil.example")),
            &hosts
        )
        .is_some());
        assert!(refusal(&HeaderMap::new(), &hosts).is_some());
    }

    #[test]
    fn tokens_are_long_and_differ() {
        let (a, b) = (new_token(), new_token());
        assert_eq!(a.len(), 32);
        assert_ne!(a, b);
        assert!(token_matches(&a, &a));
        assert!(!token_matches(&a, &b));
        assert!(!token_matches(&a, &a[..31]));
    }
}
