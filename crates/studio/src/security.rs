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

/// The `Host` values a request may carry for a server at `addr`; empty
/// for an unspecified address (`0.0.0.0`), whose names cannot be known:
/// then any `Host` passes, and an `Origin` must name the same host.
pub fn allowed_hosts(addr: SocketAddr) -> Vec<String> {
    if addr.ip().is_unspecified() {
        return Vec::new();
    }
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

/// Why a request is refused, or `None` when its `Host` is one of `hosts`
/// (any, when `hosts` is empty) and its `Origin`, if any, names that host.
pub fn refusal(headers: &HeaderMap, hosts: &[String]) -> Option<&'static str> {
    let host = headers.get(header::HOST).and_then(|v| v.to_str().ok());
    let host = match host {
        Some(host) if hosts.is_empty() || hosts.iter().any(|h| h.eq_ignore_ascii_case(host)) => {
            host
        }
        _ => return Some("the Host header does not name this server"),
    };
    if let Some(origin) = headers.get(header::ORIGIN) {
        let origin = origin.to_str().unwrap_or("");
        let own = origin
            .strip_prefix("http://")
            .is_some_and(|rest| rest.eq_ignore_ascii_case(host));
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
        // The page's origin must be the host it asked.
        assert!(refusal(
            &headers("localhost:7171", Some("http://127.0.0.1:7171")),
            &hosts
        )
        .is_some());
        let anywhere = allowed_hosts("0.0.0.0:7171".parse().unwrap());
        assert_eq!(
            refusal(
                &headers("box.lan:7171", Some("http://box.lan:7171")),
                &anywhere
            ),
            None
        );
        assert!(refusal(
            &headers("box.lan:7171", Some("http://evil.example")),
            &anywhere
        )
        .is_some());
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
