use crate::{Camera, Light};
use sv_geom::{Body, BodyKind, Geometry, Op, Term, Zone};
use sv_math::DVec3;

/// Length units of a model.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Units {
    /// Inches (the COMGEOM default).
    #[default]
    Inch,
    /// Feet.
    Foot,
    /// Millimetres.
    Millimetre,
    /// Centimetres.
    Centimetre,
    /// Metres.
    Metre,
}

impl Units {
    /// Millimetres per unit.
    pub fn mm(self) -> f64 {
        match self {
            Units::Inch => 25.4,
            Units::Foot => 304.8,
            Units::Millimetre => 1.0,
            Units::Centimetre => 10.0,
            Units::Metre => 1000.0,
        }
    }

    /// Short name as on a COMGEOM title card.
    pub fn abbrev(self) -> &'static str {
        match self {
            Units::Inch => "in",
            Units::Foot => "ft",
            Units::Millimetre => "mm",
            Units::Centimetre => "cm",
            Units::Metre => "m",
        }
    }

    /// Parse a unit name (`in`, `inch`, `mm`, …), ignoring case.
    pub fn parse(s: &str) -> Option<Units> {
        Some(match s.trim().to_ascii_lowercase().as_str() {
            "in" | "inch" | "inches" => Units::Inch,
            "ft" | "foot" | "feet" => Units::Foot,
            "mm" | "millimetre" | "millimeter" | "millimetres" | "millimeters" => Units::Millimetre,
            "cm" | "centimetre" | "centimeter" | "centimetres" | "centimeters" => Units::Centimetre,
            "m" | "metre" | "meter" | "metres" | "meters" => Units::Metre,
            _ => return None,
        })
    }
}

/// Background of the picture.
#[derive(Clone, Debug, PartialEq)]
pub enum Background {
    /// A flat colour (linear RGB; grey when all three are equal).
    Colour([f64; 3]),
}

impl Default for Background {
    fn default() -> Self {
        Background::Colour([0.0; 3])
    }
}

/// Optical properties and metadata of a region.
#[derive(Clone, Debug, PartialEq)]
pub struct RegionProps {
    /// Coefficient of reflection k (0…1).
    pub k: f64,
    /// Colour (linear RGB); `None` is white, the paper's grey picture.
    pub colour: Option<[f64; 3]>,
    /// Transparent regions let light through ("x-ray vision").
    pub transparent: bool,
    /// COMGEOM ident (item) code.
    pub ident: i64,
    /// COMGEOM air code (non-zero marks air).
    pub air: i64,
    /// Material code.
    pub material: i64,
    /// Line-of-sight thickness percent.
    pub los: i64,
    /// Density in g/cm³, when known (for masses).
    pub density: Option<f64>,
    /// Atom density in atoms per barn-centimetre, when the input gives it
    /// so (MCNP's positive cell densities).
    pub atom_density: Option<f64>,
    /// The material by name as the input names it (FLUKA's ASSIGNMA
    /// `WATER`, MCNP's `m12`, OpenMC's material name or id), and its
    /// index into [`Scene::materials`] when the input describes it.
    pub material_name: Option<String>,
    /// Index into [`Scene::materials`].
    pub material_index: Option<usize>,
    /// Beyond the model: a FLUKA black hole, an MCNP cell of importance
    /// zero, OpenMC's vacuum boundary. Never drawn or framed; for checks,
    /// the outside of the model's universe.
    pub outside: bool,
    /// Free-text description (the deck's comment column).
    pub description: String,
}

impl RegionProps {
    /// The reflectance `k` of a region that gives none.
    pub const DEFAULT_K: f64 = 0.8;
}

impl Default for RegionProps {
    fn default() -> Self {
        RegionProps {
            k: RegionProps::DEFAULT_K,
            colour: None,
            transparent: false,
            ident: 0,
            air: 0,
            material: 0,
            los: 100,
            density: None,
            atom_density: None,
            material_name: None,
            material_index: None,
            outside: false,
            description: String::new(),
        }
    }
}

/// A material as a transport code describes it: what a region is made of,
/// for listing, colouring by material and comparing two models.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Material {
    /// Its name or number as the input gives it (`m12`, `WATER`, `UO2`).
    pub name: String,
    /// Density in g/cm³, when the material itself carries one.
    pub density: Option<f64>,
    /// Atom density in atoms per barn-centimetre, when given so.
    pub atom_density: Option<f64>,
    /// What it is made of.
    pub components: Vec<Component>,
}

/// One nuclide or element of a [`Material`].
#[derive(Clone, Debug, PartialEq)]
pub struct Component {
    /// The nuclide as `Z`, `A` (0 for a natural element) and metastable
    /// state, e.g. U-235 is (92, 235, 0).
    pub zam: (u32, u32, u32),
    /// Its fraction (atom or weight, see `by_weight`), as given (not
    /// normalised).
    pub fraction: f64,
    /// True for a weight fraction, false for an atom fraction.
    pub by_weight: bool,
}

/// A complete scene: geometry, camera, lights and picture settings.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// Title (from the deck's title card or `TITLE`).
    pub title: String,
    /// Length units of the geometry.
    pub units: Units,
    /// Bodies and regions.
    pub geometry: Geometry,
    /// One entry per region, same order as `geometry.regions`.
    pub regions: Vec<RegionProps>,
    /// The materials the regions refer to ([`RegionProps::material_index`]).
    pub materials: Vec<Material>,
    /// Camera, or `None` to frame the model automatically.
    pub camera: Option<Camera>,
    /// Light sources; empty means a default light over the viewer's shoulder.
    pub lights: Vec<Light>,
    /// Ambient intensity A₀.
    pub ambient: f64,
    /// Background.
    pub background: Background,
    /// Cast shadows (a blocked light contributes nothing).
    pub shadows: bool,
    /// Raster size, when the scene sets one.
    pub size: Option<(u32, u32)>,
    /// Notes for the user produced while reading (for example "LATTICE
    /// replicas are not drawn").
    pub notes: Vec<String>,
}

impl Default for Scene {
    fn default() -> Self {
        Scene {
            title: String::new(),
            units: Units::default(),
            geometry: Geometry::default(),
            regions: Vec::new(),
            materials: Vec::new(),
            camera: None,
            lights: Vec::new(),
            ambient: 0.15,
            background: Background::default(),
            shadows: true,
            size: None,
            notes: Vec::new(),
        }
    }
}

impl Scene {
    /// When every region is transparent but some are air (which readers hide
    /// by default), show the air regions instead of an empty picture.
    /// Returns true when it did so.
    pub fn show_air_if_nothing_else(&mut self) -> bool {
        if self.regions.iter().any(|r| !r.transparent) || !self.regions.iter().any(|r| r.air != 0) {
            return false;
        }
        for r in self.regions.iter_mut().filter(|r| r.air != 0) {
            r.transparent = false;
        }
        true
    }

    /// Cut the model open: everything on the side of the plane through
    /// `point` that `normal` points to is taken away, from every region
    /// but those beyond the model, so that the section shows (a clip
    /// plane as Flair's and OpenMC's cutaway views have). The cut faces
    /// are a half-space's, named `cut N`. False (nothing done) when the
    /// normal is zero or a value is not finite.
    pub fn cut_away(&mut self, normal: DVec3, point: DVec3) -> bool {
        let ok = normal.length_squared() > 0.0 && normal.is_finite() && point.is_finite();
        if !ok {
            return false;
        }
        let n = normal.normalize();
        let body = self.geometry.bodies.len();
        let cuts = self
            .geometry
            .bodies
            .iter()
            .filter(|b| b.name.starts_with("cut "))
            .count();
        // The half-space kept: behind the plane, away from the normal.
        self.geometry.bodies.push(Body::new(
            format!("cut {}", cuts + 1),
            BodyKind::Haf,
            vec![n.x, n.y, n.z, n.dot(point)],
        ));
        let keep = Term {
            op: Op::Inside,
            body,
        };
        for (region, props) in self.geometry.regions.iter_mut().zip(&self.regions) {
            if props.outside || region.universe != 0 {
                continue;
            }
            if region.zones.is_empty() {
                region.zones.push(Zone::new(vec![keep]));
            }
            for zone in &mut region.zones {
                zone.terms.push(keep);
            }
        }
        true
    }

    /// Add a region with its properties, keeping both lists aligned.
    pub fn push_region(&mut self, region: sv_geom::Region, props: RegionProps) -> usize {
        self.geometry.regions.push(region);
        self.regions.push(props);
        self.geometry.regions.len() - 1
    }
}
