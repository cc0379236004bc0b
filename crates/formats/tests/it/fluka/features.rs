//! What real inputs do: continuation lines, `$end_…` with text after it,
//! `$name` substitution, regions too large to expand, unnamed ROT-DEFI
//! cards, voxels, materials and geometry in a separate file.

use super::*;
use sv_geom::{Fill, Term};

#[test]
fn a_line_that_starts_no_region_continues_the_one_before() {
    // CombLayer ends a line inside parentheses and goes on with `)`; nEXO
    // writes binary `+` and `-` and closes on the next line.
    let bodies: String = "abcdefg"
        .chars()
        .map(|c| format!("SPH {c} 0 0 0 1\n"))
        .collect();
    let regions = "R1 18 +( -a | +b |\n        +c ) +( +d |\n        ( +( -e | -f ) -g )\n        ) +a\nr2           5 (a + b - c) - ((d + e - f\n               ) - (g)\n               )\n";
    let l = read_text(&geo(&bodies, regions)).unwrap();
    assert_eq!(
        zones(&l, "R1"),
        ["+a +(-a | +b | +c) +(+d | -g +(-e | -f))"]
    );
    assert_eq!(zones(&l, "r2"), ["+a +b -c -(+d +e -f -g)"]);
    assert!(l.warnings.is_empty());
}

#[test]
fn a_missing_naz_is_hinted_where_the_region_was_meant() {
    let e = read_text(&geo("SPH a 0 0 0 1\nSPH b 0 0 0 2", "r 5 +b -a\nq +a")).unwrap_err();
    let d = e.errors().next().unwrap();
    assert_eq!(d.message, "region `r` refers to undefined body `q`");
    assert_eq!(d.line_col(), (9, 1));
    assert_eq!(
        d.hint.as_deref(),
        Some("a region starts with its name and NAZ number: if `q` starts one, give its NAZ after the name")
    );
}

#[test]
fn text_after_an_end_directive_is_a_warning() {
    let text = geo(
        "$start_translat 1 0 0\nSPH a 0 0 0 1\n$end_translat now\n$start_expansion 2\nSPH b 0 0 0 1\n$end_expansion 2.\nRPP w -9 9 -9 9 -9 9",
        "r 5 +w -a -b",
    );
    let l = read_text(&text).unwrap();
    assert_eq!(
        warnings(&l),
        [
            ((7, 15), "unexpected `now` after `$end_translat`: ignored"),
            ((10, 16), "unexpected `2.` after `$end_expansion`: ignored"),
        ]
    );
    assert_close(&body(&l, "a").params, &[1.0, 0.0, 0.0, 1.0]);
    assert_close(&body(&l, "b").params, &[0.0, 0.0, 0.0, 2.0]);
}

#[test]
fn defined_names_are_substituted_on_every_card() {
    let text = "#define rad 2.5\n#define hole a\n#define dx 10.\n#define tr shift\n".to_string()
        + &geo(
            "SPH a 0 0 0 $rad\nRPP w -$rad 30 -9 9 -9 9\nRPP c -1 1 -1 1 -1 1\nRPP p 9 11 -1 1 -1 1",
            "r 5 +w -$hole -c -p\nball 5 +$hole\ncell 5 +c\nproto 5 +p",
        )
        .replace("END\nGEOEND", "END\nLATTICE   , cell, , , , , , $tr\nGEOEND")
        + "ROT-DEFI  , 0, 0, 0, $dx, 0, 0, $tr\n";
    let l = read_text(&text).unwrap();
    assert_close(&body(&l, "a").params, &[0.0, 0.0, 0.0, 2.5]);
    assert_close(&body(&l, "w").params[..2], &[-2.5, 30.0]);
    assert_eq!(zones(&l, "r"), ["+w -a -c -p"]);
    assert_eq!(zones(&l, "ball"), ["+a"]);
    // The cell (at the origin) shows what lies 10 cm along x: FLUKA moves
    // a point of the cell by the transformation into the prototype.
    let Some(Fill::Universe {
        region_from_universe,
        ..
    }) = &region(&l, "cell").fill
    else {
        panic!("the cell is not filled");
    };
    let p = region_from_universe.transform_point3(sv_math::DVec3::new(10.0, 0.0, 0.0));
    assert!(p.length() < 1e-12, "{p:?}");
    // A problem in a substituted value points at the `$name` written; one
    // after it at its own column.
    let bad = "#define r x1\n".to_string() + &geo("SPH a 0 0 0 $r", "q 5 +a -nob");
    let e = errors(&bad);
    assert_eq!(e[0].0, 6);
    assert_eq!(e[0].1, 13);
    assert!(e[0].2.contains("found `x1`"), "{}", e[0].2);
    assert_eq!((e[1].0, e[1].1), (8, 9));
}

#[test]
fn a_union_of_eighteen_groups_is_read_in_time_linear_in_its_size() {
    // +sph -( +(+a1 -b1) | … | +(+an -bn) ): the tokamak's coils. Written
    // as sums of products it is 2^n zones; as written it is n groups.
    for n in [18, 4000] {
        let bodies: String = (0..n)
            .map(|i| format!("RCC a{i} {i} 0 0 0 0 1 2\nRCC b{i} {i} 0 0 0 0 1 1\n"))
            .collect::<String>()
            + "SPH sph 0 0 0 99999";
        let union: Vec<String> = (0..n).map(|i| format!("+( +a{i} -b{i} )")).collect();
        let regions = format!("WORLD 5 +sph -( {} )", union.join("|\n   "));
        let start = std::time::Instant::now();
        let l = read_text(&geo(&bodies, &regions)).unwrap();
        let seconds = start.elapsed().as_secs_f64();
        let world = region(&l, "WORLD");
        assert_eq!(world.zones.len(), 1);
        assert_eq!(world.zones[0].groups[0].zones.len(), n);
        let mut terms = 0;
        world.for_each_term(&mut |_: &Term| terms += 1);
        assert_eq!(terms, 2 * n + 1, "one term per body written");
        assert!(seconds < 20.0, "{n} groups took {seconds} s");
    }
}

#[test]
fn an_unnamed_rot_defi_is_used_by_its_index() {
    // WHAT(1) = 3, no SDUM: FLUKA calls it ROT#3; LATTICE and
    // `$start_transform` may use `ROT#3`, `ROT#003` or `3`.
    let rot = format!(
        "{:<10}{:>10}{:>10}{:>10}{:>10}\n",
        "ROT-DEFI", "3.", "", "", "-20."
    );
    for name in ["ROT#3", "ROT#003", "3"] {
        let text = geo(
            &format!("RPP proto 0 1 0 1 0 1\n$start_transform -{name}\nRPP cellb 0 1 0 1 0 1\n$end_transform\nRPP w -50 50 -50 50 -50 50"),
            "w 5 +w -proto -cellb\nproto 5 +proto\ncell 5 +cellb",
        )
        .replace("END\nGEOEND", &format!("END\nLATTICE   {:>10}{:>60}\nGEOEND", "cell", name))
            + &rot;
        let l = read_text(&text).unwrap();
        assert!(l.warnings.is_empty(), "{name}: {:?}", l.warnings);
        // The cell body is the prototype moved by the inverse: x + 20.
        assert_close(&body(&l, "cellb").params[..2], &[20.0, 21.0]);
        let Some(Fill::Universe {
            region_from_universe,
            ..
        }) = &region(&l, "cell").fill
        else {
            panic!("{name}: the cell is not filled");
        };
        let moved = body(&l, "proto").transformed(region_from_universe).unwrap();
        assert_close(&moved.params, &body(&l, "cellb").params);
    }
}

#[test]
fn a_lattice_with_no_rot_defi_keeps_its_warning() {
    let text = geo(
        "SPH a 0 0 0 1\nSPH b 5 0 0 1\nSPH w 0 0 0 9",
        "w 5 +w -a -b\nr 5 +a\nc 5 +b",
    )
    .replace("END\nGEOEND", "END\nLATTICE            c\nGEOEND");
    let l = read_text(&text).unwrap();
    assert_eq!(
        l.warnings[0].message,
        "LATTICE names no transformation: its cells are drawn empty"
    );
    assert!(l.warnings[0]
        .hint
        .as_deref()
        .unwrap()
        .contains("user routine LATTIC"));
    assert!(region(&l, "c").fill.is_none());
}

/// An input with a VOXELS card for `target.vxl` around a void.
fn voxel_input(extra: &str) -> String {
    format!(
        "GEOBEGIN                                                              COMBNAME\n\
         VOXELS           1.0       2.0       3.0{extra:>10}                    target\n\
         \x20   0    0          voxels\n\
         SPH blk 0 0 0 1000\nSPH void 0 0 0 100\nEND\n\
         BLKBODY 5 +blk -void\nVOID 5 +void -VOXEL\nEND\nGEOEND\n\
         ASSIGNMA    BLCKHOLE   BLKBODY\nASSIGNMA      VACUUM      VOID\nASSIGNMA      VACUUM     VOXEL\n\
         ASSIGNMA         AIR  VOXEL001\nASSIGNMA       WATER  VOXEL002\nASSIGNMA        LEAD  VOXEL003\n"
    )
}

#[test]
fn voxels_are_read_from_their_file_beside_the_input() {
    let d = temp_dir("vxl");
    let main = d.join("phantom.inp");
    // 3 x 2 x 2 voxels of 0.5 x 1 x 2 cm: organ 0, organ 7 (renumbered 1)
    // in the x = 0 column, organ 9 (renumbered 2) at one corner.
    let organs: Vec<i16> = (0..12)
        .map(|k| match (k % 3, k) {
            (_, 11) => 9,
            (0, _) => 7,
            _ => 0,
        })
        .collect();
    let kreg = [0, 0, 0, 0, 0, 0, 1, 0, 2];
    std::fs::write(
        d.join("target.vxl"),
        vxl([3, 2, 2], [0.5, 1.0, 2.0], &organs, &kreg),
    )
    .unwrap();
    std::fs::write(&main, voxel_input("")).unwrap();
    let l = read_path(&main).unwrap();
    assert!(l.warnings.is_empty(), "{:?}", l.warnings);
    assert_close(&body(&l, "VOXEL").params, &[1.0, 2.5, 2.0, 4.0, 3.0, 7.0]);
    assert_eq!(zones(&l, "VOID"), ["+void -VOXEL"]);
    assert_eq!(
        region_names(&l),
        ["BLKBODY", "VOID", "VOXEL001", "VOXEL002", "VOXEL003"]
    );
    // Organ 0 (VOXEL001): x = 1..2 for z = 0 (one box) and for z = 1 the
    // row y = 0 and the voxel (1, 1): two boxes. Organ 7: one column box.
    assert_eq!(region(&l, "VOXEL001").zones.len(), 3);
    assert_eq!(zones(&l, "VOXEL002"), ["+VOXEL002_1"]);
    assert_close(
        &body(&l, "VOXEL002_1").params,
        &[1.0, 1.5, 2.0, 4.0, 3.0, 7.0],
    );
    assert_close(
        &body(&l, "VOXEL003_1").params,
        &[2.0, 2.5, 3.0, 4.0, 5.0, 7.0],
    );
    let water = &l.scene.regions[l.scene.geometry.region_index("VOXEL002").unwrap()];
    assert_eq!(water.material_name.as_deref(), Some("WATER"));
    let air = &l.scene.regions[l.scene.geometry.region_index("VOXEL001").unwrap()];
    assert!(air.transparent && air.air == 1);
    // A transformation turns the structure: ROT-DEFI 1 brings model points
    // into the voxel frame, so the boxes move by its inverse.
    let turned =
        voxel_input("1.") + &format!("{:<10}{:>10}{:>10}{:>10}\n", "ROT-DEFI", "1.", "", "90.");
    std::fs::write(&main, turned).unwrap();
    let l = read_path(&main).unwrap();
    assert_eq!(body(&l, "VOXEL").kind, BodyKind::Box);
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn voxels_without_their_file_leave_the_cage_out_with_a_warning() {
    let d = temp_dir("novxl");
    let main = d.join("phantom.inp");
    std::fs::write(&main, voxel_input("")).unwrap();
    let l = read_path(&main).unwrap();
    let w: Vec<_> = l
        .warnings
        .iter()
        .map(|w| (w.line_col(), w.message.clone()))
        .collect();
    assert_eq!(w.len(), 1, "{w:?}");
    assert_eq!(w[0].0, (2, 71));
    assert!(w[0].1.starts_with("voxel file `"), "{}", w[0].1);
    assert!(w[0].1.ends_with(
        "target.vxl` not found: the voxel structure is left out (its size is in the file)"
    ));
    // Subtracting the unknown cage takes nothing away.
    assert_eq!(zones(&l, "VOID"), ["+void"]);
    assert_eq!(l.scene.geometry.regions.len(), 2);
    // A broken file is an error at the SDUM.
    std::fs::write(d.join("target.vxl"), b"not a voxel file").unwrap();
    let e = read_path(&main).unwrap_err();
    let first = e.errors().next().unwrap();
    assert_eq!(first.line_col(), (2, 71));
    assert!(
        first.message.contains("not a Fortran unformatted file"),
        "{}",
        first.message
    );
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn materials_carry_names_numbers_densities_and_elements() {
    let text = geo(
        "SPH a 0 0 0 1\nSPH b 0 0 0 2\nSPH c 0 0 0 3\nSPH d 0 0 0 4\nSPH w 0 0 0 9",
        "out 5 +w -d\nr1 5 +a\nr2 5 +b -a\nr3 5 +c -b\nr4 5 +d -c",
    ) + &fixed_card("MATERIAL", ["54.", "", "2.94", "30.", "", "136."], "XE136")
        + &fixed_card("MATERIAL", ["54.", "", "2.94", "", "", "134."], "XE134")
        + &fixed_card("MATERIAL", ["", "", "2.94", "", "", ""], "LXe")
        + &fixed_card("COMPOUND", ["0.9", "XE136", "0.1", "XE134", "", ""], "LXe")
        + &fixed_card("MATERIAL", ["", "", "1.72", "", "", ""], "HFE")
        + &fixed_card("COMPOUND", ["0.238", "HYDROGEN", "0.476", "LXe", "", ""], "HFE")
        + "ASSIGNMA    BLCKHOLE       out\nASSIGNMA         LXe        r1\nASSIGNMA         HFE        r2\n\
         ASSIGNMA         AIR        r3\nASSIGNMA         17.        r4\n";
    let l = read_text(&text).unwrap();
    let names: Vec<&str> = l.scene.materials.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(names, ["XE136", "XE134", "LXe", "HFE"]);
    let lxe = &l.scene.materials[2];
    assert_eq!(lxe.density, Some(2.94));
    let parts: Vec<_> = lxe
        .components
        .iter()
        .map(|c| (c.zam, c.fraction, c.by_weight))
        .collect();
    assert_eq!(
        parts,
        [((54, 136, 0), 0.9, false), ((54, 134, 0), 0.1, false)]
    );
    // HFE holds a compound, so its elements are not listed.
    assert!(l.scene.materials[3].components.is_empty());
    let p = |name: &str| &l.scene.regions[l.scene.geometry.region_index(name).unwrap()];
    // XE136 takes number 30 (WHAT(4)); the others follow in order.
    let numbers: Vec<i64> = ["r1", "r2", "r3", "r4"]
        .iter()
        .map(|r| p(r).material)
        .collect();
    assert_eq!(numbers, [32, 33, 34, 17]);
    assert_eq!(p("r1").material_index, Some(2));
    assert_eq!(p("r1").density, Some(2.94));
    assert_eq!(p("r4").material_name.as_deref(), Some("LEAD"));
    assert!(p("r3").transparent && p("r3").air == 1 && !p("r3").outside);
    assert!(p("out").outside && p("out").transparent && p("out").air == 0);
}

#[test]
fn the_geometry_may_be_read_from_a_separate_file() {
    let d = temp_dir("geofile");
    std::fs::create_dir_all(d.join("geo")).unwrap();
    let geometry = "    0    0          separate\nSPH a 0 0 0 1\nSPH w 0 0 0 9\nEND\nw 5 +w -a\nin 5 +a -nob\nEND\n";
    std::fs::write(d.join("geo/world.geo"), geometry).unwrap();
    let main = d.join("main.inp");
    let input = fixed_card("GEOBEGIN", ["", "0.1", "53.", "54.", "", ""], "COMBNAME")
        + "geo/world.geo\nout.scr\nGEOEND\nASSIGNMA      VACUUM        in\n";
    std::fs::write(&main, input).unwrap();
    // The error is located in the geometry file.
    let e = read_path(&main).unwrap_err();
    let first = e.errors().next().unwrap();
    assert!(
        first.source.name.ends_with("world.geo"),
        "{}",
        first.source.name
    );
    assert_eq!(first.line_col(), (6, 10));
    std::fs::write(d.join("geo/world.geo"), geometry.replace(" -nob", "")).unwrap();
    let l = read_path(&main).unwrap();
    assert_eq!(l.scene.title, "separate");
    assert_eq!(l.scene.geometry.bodies.len(), 2);
    assert_eq!(zones(&l, "w"), ["+w -a"]);
    assert_eq!(l.scene.regions[1].material_name.as_deref(), Some("VACUUM"));
    // A missing file is an error on the card that names it.
    std::fs::remove_file(d.join("geo/world.geo")).unwrap();
    let e = read_path(&main).unwrap_err();
    let first = e.errors().next().unwrap();
    assert_eq!(first.line_col(), (2, 1));
    assert!(
        first.message.starts_with("cannot read the geometry file"),
        "{}",
        first.message
    );
    let _ = std::fs::remove_dir_all(&d);
}
