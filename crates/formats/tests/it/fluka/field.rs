//! The inputs physicists wrote (../shared/decks/fluka/field, README there):
//! each is read, and its counts are the ones counted in the file (bodies
//! between the title line and the first END, regions up to the second,
//! MATERIAL cards, ASSIGNMA materials).

use super::*;

/// A field input, read; `None` when the shared decks are skipped.
fn field(name: &str) -> Option<Loaded> {
    let dir = sv_testdata::shared_decks("fluka/field")?;
    match read_path(&dir.join(name)) {
        Ok(l) => Some(l),
        Err(d) => panic!("{name} failed:\n{}", d.render_plain()),
    }
}

/// Bodies, regions and materials of a scene.
fn counts(l: &Loaded) -> (usize, usize, usize) {
    let g = &l.scene.geometry;
    (g.bodies.len(), g.regions.len(), l.scene.materials.len())
}

/// How many regions are made of `material`.
fn made_of(l: &Loaded, material: &str) -> usize {
    l.scene
        .regions
        .iter()
        .filter(|p| p.material_name.as_deref() == Some(material))
        .count()
}

#[test]
fn every_field_input_loads() {
    let Some(mut files) = sv_testdata::shared_files("fluka/field", &[".inp"]) else {
        return;
    };
    files.extend(sv_testdata::shared_files("fluka/field/cosmic_atm", &[".inp"]).unwrap());
    let mut refused = Vec::new();
    for f in &files {
        if let Err(d) = read_path(f) {
            refused.push(format!("{}:\n{}", f.display(), d.render_plain()));
        }
    }
    // bokko_voxel.inp names a body `blkbody` it never defines (see below).
    assert_eq!(refused.len(), 1, "{}", refused.join("\n"));
    assert!(refused[0].contains("bokko_voxel.inp"), "{}", refused[0]);
}

#[test]
fn nexo_closes_parentheses_on_continuation_lines() {
    let Some(l) = field("nexo_2024.inp") else {
        return;
    };
    assert_eq!(counts(&l), (42, 17, 11));
    // `od_in 5 (…) - o_cryo_o - (…) - ((sup_ocol + sup_top - sup_bot` then
    // a line `) - (…)) - ((…) - (…` and a line `))`.
    assert_eq!(
        zones(&l, "od_in"),
        ["+od_icol +wtrsurf -od_ibot -o_cryo_o -(+oc_con_o -oc_con_i) -(+sup_ocol +sup_top -sup_bot -(+sup_icol +sup_itop -sup_ibot)) -(+ft_col_o +ft_top -ft_bot -(+ft_col_i +ft_top -ft_bot))"]
    );
    assert_eq!(made_of(&l, "AIR"), 2);
    let lxe = l.scene.materials.iter().find(|m| m.name == "LXe").unwrap();
    assert_eq!(lxe.density, Some(2.94));
    let parts: Vec<_> = lxe.components.iter().map(|c| (c.zam, c.fraction)).collect();
    assert_eq!(parts, [((54, 136, 0), 0.9), ((54, 134, 0), 0.1)]);
}

#[test]
fn comblayer_output_with_hundreds_of_regions() {
    let Some(l) = field("ansell_beamstop_novar.inp") else {
        return;
    };
    assert_eq!(counts(&l), (305, 328, 73));
    assert_eq!(made_of(&l, "VACUUM"), 131);
    assert_eq!(made_of(&l, "BLCKHOLE"), 1);
    assert_eq!(l.scene.regions.iter().filter(|p| p.air == 1).count(), 131);
    // R4140003 18 +( … 6 terms ) +( … | ( +( … ) … ) \n ) +s4125005 …
    let r = region(&l, "R4140003");
    assert_eq!(r.zones.len(), 1);
    assert_eq!(r.zones[0].terms.len(), 6);
    assert_eq!(r.zones[0].groups.len(), 2);
    assert_eq!(r.zones[0].groups[0].zones.len(), 6);
    assert_eq!(r.zones[0].groups[1].zones.len(), 4);
    assert_eq!(r.zones[0].depth(), 2);
}

#[test]
fn the_tokamak_keeps_its_unions_of_coils_and_wall_segments() {
    let Some(l) = field("tt1_runaway.inp") else {
        return;
    };
    assert_eq!(counts(&l), (83, 8, 9));
    // WORLD 5 +sph2 -( +( +TF1o -TF1i ) | … 16 coils ) -( … 16 wall
    // segments ) -detout: 2^32 zones if expanded, one zone with two groups
    // of 16 here.
    let world = region(&l, "WORLD");
    assert_eq!(world.zones.len(), 1);
    assert_eq!(world.zones[0].terms.len(), 2);
    let groups: Vec<usize> = world.zones[0]
        .groups
        .iter()
        .map(|g| g.zones.len())
        .collect();
    assert_eq!(groups, [16, 16]);
    assert_eq!(made_of(&l, "BLCKHOLE"), 1);
    assert_eq!(made_of(&l, "AIR") + made_of(&l, "VACUUM"), 2);
}

#[test]
fn a_small_geometry_with_a_compound() {
    let Some(l) = field("cosmic_step2_geometry.inp") else {
        return;
    };
    assert_eq!(counts(&l), (4, 4, 1));
    let mater = &l.scene.materials[0];
    assert_eq!((mater.name.as_str(), mater.density), ("mater", Some(1.023)));
    let parts: Vec<_> = mater
        .components
        .iter()
        .map(|c| (c.zam, c.fraction, c.by_weight))
        .collect();
    assert_eq!(parts, [((6, 0, 0), 8.0, false), ((1, 0, 0), 8.0, false)]);
    assert_eq!(made_of(&l, "AIR"), 2);
    let box_ = &l.scene.regions[l.scene.geometry.region_index("Box").unwrap()];
    assert_eq!(box_.material_index, Some(0));
    assert_eq!(box_.density, Some(1.023));
}

#[test]
fn the_atmosphere_is_read_from_its_geometry_file() {
    let Some(l) = field("cosmic_atm/try.inp") else {
        return;
    };
    // atmloc.geo: 106 bodies, 206 regions; atmomat.cards: AIR001…AIR100.
    assert_eq!(counts(&l), (106, 206, 100));
    assert_eq!(
        l.scene.title,
        "All Particle flux at DongGuan, 22.86N° 113.92E°"
    );
    assert_eq!(made_of(&l, "BLCKHOLE"), 5);
    assert_eq!(made_of(&l, "VACUUM"), 1);
    // The later ASSIGNMA cards of the included files win over the first.
    let air = &l.scene.regions[l.scene.geometry.region_index("Air042").unwrap()];
    assert_eq!(air.material_name.as_deref(), Some("AIR042"));
    assert_eq!(
        zones(&l, "Side100"),
        [
            "-lay101 +lay100 -scutcone -cutcone2",
            "-lay101 +lay100 +cutcone3 -scutcone"
        ]
    );
}

#[test]
fn the_voxel_input_reads_its_voxels_card_and_names_its_missing_body() {
    let Some(dir) = sv_testdata::shared_decks("fluka/field") else {
        return;
    };
    let text = std::fs::read_to_string(dir.join("bokko_voxel.inp")).unwrap();
    // The input subtracts `blkbody`, which it never defines: FLUKA's rule
    // that a region names defined bodies holds. The VOXELS card before the
    // title line is read as such (no "expected a body type").
    let e = errors(&text);
    assert_eq!(
        e,
        [(
            17,
            17,
            "region `BLKBODY` refers to undefined body `blkbody`".to_string()
        )]
    );
    // With the body defined and the voxel file beside it (a 3 x 2 x 1 grid
    // of organs 0 to 5), it loads with its six voxel regions' materials.
    let d = temp_dir("bokko");
    let fixed = text.replace("SPH void", "SPH blkbody    0.0 0.0 0.0 100000.0\nSPH void");
    std::fs::write(d.join("voxel.inp"), &fixed).unwrap();
    let l = read_path(&d.join("voxel.inp")).unwrap();
    assert_eq!(l.warnings.len(), 1, "{:?}", l.warnings);
    assert!(l.warnings[0].message.contains("target.vxl` not found"));
    assert_eq!(counts(&l), (2, 2, 0));
    std::fs::write(
        d.join("target.vxl"),
        vxl(
            [3, 2, 1],
            [1.0, 1.0, 1.0],
            &[0, 1, 2, 3, 4, 5],
            &[1, 2, 3, 4, 5],
        ),
    )
    .unwrap();
    let l = read_path(&d.join("voxel.inp")).unwrap();
    assert!(l.warnings.is_empty(), "{:?}", l.warnings);
    assert_eq!(
        region_names(&l),
        [
            "BLKBODY", "VOID", "VOXEL001", "VOXEL002", "VOXEL003", "VOXEL004", "VOXEL005",
            "VOXEL006"
        ]
    );
    let materials: Vec<_> = l
        .scene
        .regions
        .iter()
        .map(|p| p.material_name.as_deref().unwrap())
        .collect();
    assert_eq!(
        materials,
        ["BLCKHOLE", "VACUUM", "VACUUM", "HYDROGEN", "HELIUM", "BERYLLIU", "CARBON", "NITROGEN"]
    );
    let _ = std::fs::remove_dir_all(&d);
}
