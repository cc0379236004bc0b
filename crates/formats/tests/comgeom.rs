use sv_formats::{comgeom, LoadOptions, SourceFile};
const DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared/decks/comgeom/");
#[test]
fn smoke() {
    for f in ["vdeck-all-types.cg", "gift-sample-target-v4.cg", "mep021a-generator-v5.cg"] {
        let text = std::fs::read_to_string(format!("{DIR}{f}")).unwrap();
        println!("{f}: {:?}", comgeom::detect_version(&text));
        match comgeom::read(&SourceFile::new(f, text), &LoadOptions::default()) {
            Ok(l) => { println!("{} bodies {} regions", l.scene.geometry.bodies.len(), l.scene.geometry.regions.len()); for w in &l.warnings { println!("{}", w.render_plain()); } }
            Err(d) => println!("{}", d.render_plain()),
        }
    }
}
