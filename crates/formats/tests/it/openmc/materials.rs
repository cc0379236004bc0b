//! Materials by id and name: components, fractions, density units, void
//! and distributed materials, model.xml.

use super::*;
use sv_scene::Component;

/// A geometry of one cell of material 1 with `materials` as its
/// materials.xml.
fn with_materials(materials: &str) -> Result<Loaded, Diagnostics> {
    openmc::read_with_materials(
        &SourceFile::new(
            "geometry.xml",
            r#"<geometry><cell id="1" material="1"/></geometry>"#,
        ),
        Some(&SourceFile::new("materials.xml", materials)),
    )
}

/// The (density, atom density) of material 1 with `<density>` and nuclides.
fn densities(density: &str, nuclides: &str) -> (Option<f64>, Option<f64>) {
    let l = with_materials(&format!(
        r#"<materials><material id="1">{density}{nuclides}</material></materials>"#
    ))
    .unwrap_or_else(|d| panic!("{}", d.render_plain()));
    let m = &l.scene.materials[0];
    assert_eq!(l.scene.regions[0].density, m.density);
    assert_eq!(l.scene.regions[0].atom_density, m.atom_density);
    (m.density, m.atom_density)
}

#[test]
fn density_units_are_converted() {
    let u = r#"<nuclide name="U235" ao="1"/>"#;
    assert_eq!(
        densities(r#"<density value="18.7" units="g/cm3"/>"#, u),
        (Some(18.7), None)
    );
    assert_eq!(
        densities(r#"<density value="18.7" units="g/cc"/>"#, u),
        (Some(18.7), None)
    );
    assert_eq!(
        densities(r#"<density value="1000" units="kg/m3"/>"#, u),
        (Some(1.0), None)
    );
    assert_eq!(
        densities(r#"<density value="0.048" units="atom/b-cm"/>"#, u),
        (None, Some(0.048))
    );
    let (_, atoms) = densities(r#"<density value="4.8e22" units="atom/cm3"/>"#, u);
    assert!((atoms.unwrap() - 0.048).abs() < 1e-15);
    let two = r#"<nuclide name="H1" ao="0.0667"/><nuclide name="O16" ao="0.0333"/>"#;
    let (_, atoms) = densities(r#"<density units="sum"/>"#, two);
    assert!((atoms.unwrap() - 0.1).abs() < 1e-15);
    let weights = r#"<nuclide name="H1" wo="0.1"/><nuclide name="O16" wo="0.9"/>"#;
    let (grams, _) = densities(r#"<density units="sum"/>"#, weights);
    assert!((grams.unwrap() - 1.0).abs() < 1e-15);
    assert_eq!(
        densities(
            r#"<density value="2" units="macro"/>"#,
            r#"<macroscopic name="UO2"/>"#
        ),
        (None, None)
    );
}

#[test]
fn components_are_nuclides_and_elements_by_atom_or_weight() {
    let l = with_materials(
        r#"<materials>
  <material id="1" name="mix">
    <density value="1" units="g/cm3"/>
    <nuclide name="U235" wo="0.5"/>
    <nuclide name="Am242_m1" wo="0.25"/>
    <nuclide name="C0" wo="0.15"/>
    <element name="Fe" wo="0.1"/>
  </material>
</materials>"#,
    )
    .unwrap();
    let m = &l.scene.materials[0];
    assert_eq!(m.name, "mix");
    let c = |zam, fraction| Component {
        zam,
        fraction,
        by_weight: true,
    };
    assert_eq!(
        m.components,
        [
            c((92, 235, 0), 0.5),
            c((95, 242, 1), 0.25),
            c((6, 0, 0), 0.15),
            c((26, 0, 0), 0.1)
        ]
    );
}

#[test]
fn cells_name_their_material_by_id_and_name() {
    let l = model(
        r#"<cell id="1" material="2" region="" name="moderator"/>
<cell id="2" universe="3" material="void"/>
<cell id="3" universe="4" material="1" density="10.5"/>"#,
    );
    let p = &l.scene.regions;
    assert_eq!(p[0].material, 2);
    assert_eq!(p[0].material_name.as_deref(), Some("water"));
    assert_eq!(p[0].material_index, Some(1));
    assert_eq!(p[0].description, "moderator");
    assert!((p[0].atom_density.unwrap() - 0.1).abs() < 1e-15);
    assert!(!p[0].transparent);
    // Void is air: hidden unless asked for.
    assert_eq!((p[1].material, p[1].material_name.clone()), (0, None));
    assert!(p[1].transparent && p[1].air != 0);
    // A cell's own density overrides its material's.
    assert_eq!((p[2].density, p[2].atom_density), (Some(10.5), None));
    assert_eq!(l.scene.materials.len(), 2);
    assert_eq!(l.scene.materials[0].name, "fuel");
}

#[test]
fn a_material_without_a_name_is_known_by_its_id() {
    let l = with_materials(
        r#"<materials><material id="1"><density value="1" units="g/cc"/><nuclide name="H1" ao="1"/></material></materials>"#,
    )
    .unwrap();
    assert_eq!(l.scene.regions[0].material_name.as_deref(), Some("1"));
}

#[test]
fn distributed_materials_use_the_first_with_a_warning() {
    let l = model(r#"<cell id="1" material="2 1 void"/>"#);
    assert_eq!(l.scene.regions[0].material_name.as_deref(), Some("water"));
    assert_eq!(l.warnings.len(), 1);
    assert_eq!(
        l.warnings[0].message,
        "cell 1 lists 3 materials, one per instance: every instance is drawn with the first"
    );
}

#[test]
fn without_materials_xml_materials_are_known_by_id() {
    let l = openmc::read_with_materials(
        &SourceFile::new(
            "geometry.xml",
            r#"<geometry><cell id="1" material="4"/></geometry>"#,
        ),
        None,
    )
    .unwrap();
    assert_eq!(l.scene.regions[0].material_name.as_deref(), Some("4"));
    assert_eq!(l.scene.regions[0].material_index, None);
    assert_eq!(
        l.warnings[0].message,
        "no materials.xml beside this geometry: materials are known by id only"
    );
}

#[test]
fn model_xml_holds_geometry_and_materials() {
    let text = format!(
        r#"<?xml version="1.0"?>
<model>
  {}
  <geometry>
    <surface id="1" type="sphere" coeffs="0 0 0 3"/>
    <cell id="9" material="1" region="-1"/>
  </geometry>
  <settings><particles>100</particles></settings>
</model>"#,
        MATERIALS.trim_start_matches(r#"<?xml version="1.0"?>"#)
    );
    let l = openmc::read_with_materials(&SourceFile::new("model.xml", text), None).unwrap();
    assert_eq!(l.scene.materials.len(), 2);
    assert_eq!(l.scene.regions[0].material_name.as_deref(), Some("fuel"));
    assert_eq!(l.scene.units, sv_scene::Units::Centimetre);
    assert_eq!(l.format, sv_formats::Format::OpenMc);
}

#[test]
fn material_errors_are_located_in_materials_xml() {
    let e = errors_of(with_materials(
        r#"<materials>
  <material id="1"><density value="1" units="g/m3"/><nuclide name="U235" ao="1"/></material>
  <material id="2"><density value="-1" units="g/cc"/><nuclide name="Uu235" ao="1"/></material>
  <material id="3"><density units="sum"/><nuclide name="H1" ao="1" wo="1"/><nuclide name="O16"/></material>
  <material id="4"><nuclide name="H1" ao="1"/></material>
  <material id="5"><density units="sum"/><nuclide name="H1" ao="1"/><nuclide name="O16" wo="1"/></material>
  <material id="4"><density units="sum"/><nuclide name="H1" ao="1"/></material>
</materials>"#,
    ));
    assert_eq!(
        by_place(&e),
        [
            (2, 46, "unknown density units `g/m3`"),
            (3, 69, "`Uu235` is not a nuclide or element name"),
            (4, 72, "`H1` has both an atom and a weight fraction"),
            (4, 91, "`O16` has no atom (ao) or weight (wo) fraction"),
            (5, 3, "material 4 has no <density>"),
            (6, 3, "material 5 mixes atom and weight fractions"),
            (7, 17, "material 4 is defined twice"),
        ]
    );
    // A cell's undefined material, or a density it cannot have, is an
    // error in the geometry.
    let e = errors(
        r#"<cell id="1" material="3"/>
<cell id="2" universe="2" material="void" density="2"/>
<cell id="3" universe="3" material="1" density="0"/>"#,
    );
    assert_eq!(
        by_place(&e),
        [
            (2, 24, "material 3 is not defined in materials.xml"),
            (
                3,
                52,
                "only a cell of (non-void) material can have a density"
            ),
            (4, 49, "a cell density must be positive"),
        ]
    );
}
