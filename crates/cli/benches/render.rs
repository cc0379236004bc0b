//! Primary-ray throughput on the bundled examples (criterion).
//!
//! `cargo bench -p synthavision` — figures are recorded in BENCHMARKS.md.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use std::path::Path;
use sv_formats::{load_file, LoadOptions};
use sv_render::{Renderer, Settings};

fn bench(c: &mut Criterion) {
    let examples = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    let mut g = c.benchmark_group("primary rays, 1 thread, 480x360");
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    for (name, file) in [
        ("figure1", "figure1/figure1.sv"),
        ("helicopter", "helicopter/helicopter.sv"),
    ] {
        let scene = load_file(&examples.join(file), &LoadOptions::default())
            .unwrap()
            .scene;
        let (r, _) = Renderer::new(&scene, 4.0 / 3.0).unwrap();
        for shadows in [false, true] {
            let st = Settings {
                width: 480,
                height: 360,
                shadows,
                samples: 1,
                aovs: false,
            };
            g.throughput(Throughput::Elements(480 * 360));
            g.bench_function(
                format!("{name}, shadows {}", if shadows { "on" } else { "off" }),
                |b| b.iter(|| pool.install(|| r.render(&st, &|_| {}))),
            );
        }
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
