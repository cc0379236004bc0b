//! The one table of body types. It feeds the readers, the writers, the
//! documentation, `synthavision bodies` and the transform code, so a body type
//! is described exactly once.

use crate::body::Prepare;
use crate::shape::{cone, ellipsoid, mesh, polyhedron, quadric, rpp, sphere, torus};
use std::fmt;

/// How a parameter behaves under a transform.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ParamKind {
    /// A point (three values): moved by the whole transform.
    Point,
    /// A vector (three values): turned and scaled, not moved.
    Vector,
    /// A length (one value): scaled by an expansion.
    Length,
    /// A number without units (a ratio, a count, a face code).
    Number,
}

impl ParamKind {
    /// How many values the parameter takes on a card.
    pub fn width(self) -> usize {
        match self {
            ParamKind::Point | ParamKind::Vector => 3,
            ParamKind::Length | ParamKind::Number => 1,
        }
    }
}

/// One named parameter of a body type.
#[derive(Clone, Copy, Debug)]
pub struct Param {
    /// Short name as in the card layouts (`V`, `H`, `R`).
    pub name: &'static str,
    /// What it is.
    pub kind: ParamKind,
    /// One line of documentation.
    pub doc: &'static str,
}

const fn p(name: &'static str, kind: ParamKind, doc: &'static str) -> Param {
    Param { name, kind, doc }
}

use ParamKind::{Length as L, Number as N, Point as P, Vector as V};

macro_rules! kinds {
    ($($variant:ident $name:literal [$($alias:literal),*] $family:literal $doc:literal [$($param:expr),* $(,)?] => $prepare:path;)*) => {
        /// Every body type SynthaVision knows.
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
        #[allow(missing_docs)]
        pub enum BodyKind { $($variant),* }

        /// The table: one entry per [`BodyKind`], in declaration order.
        pub static BODY_TYPES: &[BodyType] = &[
            $(BodyType {
                kind: BodyKind::$variant,
                name: $name,
                aliases: &[$($alias),*],
                family: $family,
                doc: $doc,
                params: &[$($param),*],
                prepare: $prepare,
            }),*
        ];
    };
}

/// The description of one body type.
#[derive(Debug)]
pub struct BodyType {
    /// The kind.
    pub kind: BodyKind,
    /// Canonical (native scene language) name.
    pub name: &'static str,
    /// Other spellings accepted by the native language.
    pub aliases: &'static [&'static str],
    /// Where the type comes from (`MAGI`, `GIFT`, `BRL-CAD`, `FLUKA`).
    pub family: &'static str,
    /// What the body is.
    pub doc: &'static str,
    /// The parameters, in card order. Empty for ARS, whose size varies.
    pub params: &'static [Param],
    /// Checks a body's values and makes its shape (in the body family's
    /// file under [`crate::shape`]); [`crate::prepare`] calls it once the
    /// values' count and finiteness are checked.
    pub prepare: Prepare,
}

impl BodyType {
    /// Number of values on the cards (fixed-size types only).
    pub fn value_count(&self) -> usize {
        self.params.iter().map(|p| p.kind.width()).sum()
    }
}

kinds! {
    Sph "SPH" [] "MAGI" "sphere: centre V, radius R" [p("V", P, "centre"), p("R", L, "radius")] => sphere::prepare_sph;
    Rcc "RCC" [] "MAGI" "right circular cylinder: base centre V, height vector H, radius R"
        [p("V", P, "base centre"), p("H", V, "height vector"), p("R", L, "radius")] => cone::prepare_rcc;
    Rec "REC" [] "MAGI" "right elliptic cylinder: base centre V, height H, semi-axes A and B"
        [p("V", P, "base centre"), p("H", V, "height vector"), p("A", V, "semi-axis A"), p("B", V, "semi-axis B")] => cone::prepare_rec;
    Trc "TRC" [] "MAGI" "truncated right circular cone: base V, height H, radii R1 (base) and R2 (top)"
        [p("V", P, "base centre"), p("H", V, "height vector"), p("R1", L, "base radius"), p("R2", L, "top radius")] => cone::prepare_trc;
    Tec "TEC" [] "MAGI" "truncated elliptic cone: base V, height H, base semi-axes A, B; top axes A/P, B/P"
        [p("V", P, "base centre"), p("H", V, "height vector"), p("A", V, "base semi-axis A"), p("B", V, "base semi-axis B"), p("P", N, "ratio of base to top axes")] => cone::prepare_tec;
    Ell "ELL" [] "MAGI" "ellipsoid of revolution by its foci F1, F2 and the full major-axis length L"
        [p("F1", P, "first focus"), p("F2", P, "second focus"), p("L", L, "length of the major axis")] => ellipsoid::prepare_ell;
    Ell1 "ELL1" [] "GIFT" "ellipsoid of revolution: centre V, semi-major axis vector A, radius of revolution R"
        [p("V", P, "centre"), p("A", V, "semi-major axis"), p("R", L, "radius of revolution")] => ellipsoid::prepare_ell1;
    Ellg "ELLG" [] "BRL-CAD" "general ellipsoid: centre V, three semi-axis vectors A, B, C"
        [p("V", P, "centre"), p("A", V, "semi-axis A"), p("B", V, "semi-axis B"), p("C", V, "semi-axis C")] => ellipsoid::prepare_ellg;
    Rpp "RPP" [] "MAGI" "axis-aligned box: xmin xmax ymin ymax zmin zmax"
        [p("XMIN", L, "x min"), p("XMAX", L, "x max"), p("YMIN", L, "y min"), p("YMAX", L, "y max"), p("ZMIN", L, "z min"), p("ZMAX", L, "z max")] => rpp::prepare_rpp;
    Box "BOX" [] "MAGI" "box: vertex V and three perpendicular edge vectors"
        [p("V", P, "vertex"), p("A", V, "edge A"), p("B", V, "edge B"), p("C", V, "edge C")] => polyhedron::prepare_box;
    Raw "RAW" ["WED"] "MAGI" "right-angle wedge: right triangle (V, V+A, V+B) swept along C"
        [p("V", P, "vertex"), p("A", V, "leg A"), p("B", V, "leg B"), p("C", V, "sweep")] => polyhedron::prepare_raw;
    Arb4 "ARB4" [] "MAGI" "tetrahedron: 4 vertices" [p("P1", P, ""), p("P2", P, ""), p("P3", P, ""), p("P4", P, "")] => polyhedron::prepare_arb;
    Arb5 "ARB5" [] "MAGI" "pyramid: base P1..P4, apex P5"
        [p("P1", P, ""), p("P2", P, ""), p("P3", P, ""), p("P4", P, ""), p("P5", P, "")] => polyhedron::prepare_arb;
    Arb6 "ARB6" [] "MAGI" "wedge: base P1..P4, ridge P5 (over P1-P2), P6 (over P3-P4)"
        [p("P1", P, ""), p("P2", P, ""), p("P3", P, ""), p("P4", P, ""), p("P5", P, ""), p("P6", P, "")] => polyhedron::prepare_arb;
    Arb7 "ARB7" [] "MAGI" "7-vertex polyhedron" [p("P1", P, ""), p("P2", P, ""), p("P3", P, ""), p("P4", P, ""), p("P5", P, ""), p("P6", P, ""), p("P7", P, "")] => polyhedron::prepare_arb;
    Arb8 "ARB8" [] "MAGI" "hexahedron: face P1..P4 and opposite face P5..P8"
        [p("P1", P, ""), p("P2", P, ""), p("P3", P, ""), p("P4", P, ""), p("P5", P, ""), p("P6", P, ""), p("P7", P, ""), p("P8", P, "")] => polyhedron::prepare_arb;
    Tgc "TGC" [] "BRL-CAD" "truncated general cone: base V, height H, base semi-axes A, B; top semi-axes C, D along A, B"
        [p("V", P, "base centre"), p("H", V, "height vector"), p("A", V, "base semi-axis A"), p("B", V, "base semi-axis B"), p("C", L, "top semi-axis along A"), p("D", L, "top semi-axis along B")] => cone::prepare_tgc;
    Tor "TOR" [] "BRL-CAD" "torus: centre V, normal N, major radius R1, minor radius R2"
        [p("V", P, "centre"), p("N", V, "normal"), p("R1", L, "major radius"), p("R2", L, "minor radius")] => torus::prepare_tor;
    Haf "HAF" [] "BRL-CAD" "half-space N·x <= D: outward normal N, distance D"
        [p("N", V, "outward normal"), p("D", L, "distance from origin along N")] => polyhedron::prepare_haf;
    Ars "ARS" [] "GIFT" "faceted solid from curves of points (closed polyhedral surface)" [] => mesh::prepare_ars;
    Xyp "XYP" [] "FLUKA" "half-space z < Z" [p("Z", L, "plane z")] => polyhedron::prepare_axis_plane;
    Xzp "XZP" [] "FLUKA" "half-space y < Y" [p("Y", L, "plane y")] => polyhedron::prepare_axis_plane;
    Yzp "YZP" [] "FLUKA" "half-space x < X" [p("X", L, "plane x")] => polyhedron::prepare_axis_plane;
    Pla "PLA" [] "FLUKA" "half-space behind a plane: outward normal N, point V"
        [p("N", V, "outward normal"), p("V", P, "point on the plane")] => polyhedron::prepare_pla;
    Xcc "XCC" [] "FLUKA" "infinite circular cylinder along x: centre y, z and radius R"
        [p("Y", L, "axis y"), p("Z", L, "axis z"), p("R", L, "radius")] => quadric::prepare_axis_cylinder;
    Ycc "YCC" [] "FLUKA" "infinite circular cylinder along y: centre z, x and radius R"
        [p("Z", L, "axis z"), p("X", L, "axis x"), p("R", L, "radius")] => quadric::prepare_axis_cylinder;
    Zcc "ZCC" [] "FLUKA" "infinite circular cylinder along z: centre x, y and radius R"
        [p("X", L, "axis x"), p("Y", L, "axis y"), p("R", L, "radius")] => quadric::prepare_axis_cylinder;
    Xec "XEC" [] "FLUKA" "infinite elliptic cylinder along x: centre y, z and semi-axes Ly, Lz"
        [p("Y", L, "axis y"), p("Z", L, "axis z"), p("LY", L, "semi-axis along y"), p("LZ", L, "semi-axis along z")] => quadric::prepare_axis_cylinder;
    Yec "YEC" [] "FLUKA" "infinite elliptic cylinder along y: centre z, x and semi-axes Lz, Lx"
        [p("Z", L, "axis z"), p("X", L, "axis x"), p("LZ", L, "semi-axis along z"), p("LX", L, "semi-axis along x")] => quadric::prepare_axis_cylinder;
    Zec "ZEC" [] "FLUKA" "infinite elliptic cylinder along z: centre x, y and semi-axes Lx, Ly"
        [p("X", L, "axis x"), p("Y", L, "axis y"), p("LX", L, "semi-axis along x"), p("LY", L, "semi-axis along y")] => quadric::prepare_axis_cylinder;
    Qua "QUA" [] "FLUKA" "quadric Axx x²+Ayy y²+Azz z²+Axy xy+Axz xz+Ayz yz+Ax x+Ay y+Az z+A0 < 0"
        [p("AXX", N, ""), p("AYY", N, ""), p("AZZ", N, ""), p("AXY", N, ""), p("AXZ", N, ""), p("AYZ", N, ""), p("AX", N, ""), p("AY", N, ""), p("AZ", N, ""), p("A0", N, "")] => quadric::prepare_qua;
    ArbF "ARBF" [] "FLUKA" "FLUKA ARB: 8 vertices and 6 face codes such as 1234 (0 for an unused face)"
        [p("P1", P, ""), p("P2", P, ""), p("P3", P, ""), p("P4", P, ""), p("P5", P, ""), p("P6", P, ""), p("P7", P, ""), p("P8", P, ""),
         p("F1", N, "face code"), p("F2", N, "face code"), p("F3", N, "face code"), p("F4", N, "face code"), p("F5", N, "face code"), p("F6", N, "face code")] => polyhedron::prepare_arbf;
}

impl BodyKind {
    /// The table entry.
    pub fn info(self) -> &'static BodyType {
        &BODY_TYPES[self as usize]
    }

    /// Canonical name.
    pub fn name(self) -> &'static str {
        self.info().name
    }

    /// Look a type up by name or alias, ignoring case.
    pub fn from_name(s: &str) -> Option<BodyKind> {
        BODY_TYPES
            .iter()
            .find(|t| {
                t.name.eq_ignore_ascii_case(s)
                    || t.aliases.iter().any(|a| a.eq_ignore_ascii_case(s))
            })
            .map(|t| t.kind)
    }

    /// True for bodies that extend to infinity.
    pub fn is_infinite(self) -> bool {
        use BodyKind::*;
        matches!(
            self,
            Haf | Xyp | Xzp | Yzp | Pla | Xcc | Ycc | Zcc | Xec | Yec | Zec | Qua
        )
    }
}

impl fmt::Display for BodyKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_is_in_enum_order_and_names_are_unique() {
        for (i, t) in BODY_TYPES.iter().enumerate() {
            assert_eq!(t.kind as usize, i, "{} is out of order", t.name);
            assert_eq!(BodyKind::from_name(t.name), Some(t.kind));
            for a in t.aliases {
                assert_eq!(BodyKind::from_name(a), Some(t.kind));
            }
        }
        let mut names: Vec<_> = BODY_TYPES
            .iter()
            .flat_map(|t| std::iter::once(t.name).chain(t.aliases.iter().copied()))
            .collect();
        names.sort();
        let n = names.len();
        names.dedup();
        assert_eq!(n, names.len(), "duplicate body type names");
    }

    #[test]
    fn value_counts_match_the_card_layouts() {
        let expect = [
            ("SPH", 4),
            ("RCC", 7),
            ("REC", 12),
            ("TRC", 8),
            ("TEC", 13),
            ("ELL", 7),
            ("ELL1", 7),
            ("ELLG", 12),
            ("RPP", 6),
            ("BOX", 12),
            ("RAW", 12),
            ("ARB4", 12),
            ("ARB5", 15),
            ("ARB6", 18),
            ("ARB7", 21),
            ("ARB8", 24),
            ("TGC", 14),
            ("TOR", 8),
            ("HAF", 4),
            ("PLA", 6),
            ("XCC", 3),
            ("XEC", 4),
            ("QUA", 10),
            ("ARBF", 30),
        ];
        for (name, n) in expect {
            assert_eq!(
                BodyKind::from_name(name).unwrap().info().value_count(),
                n,
                "{name}"
            );
        }
    }
}
