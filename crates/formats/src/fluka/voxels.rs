//! The VOXELS card and its `.vxl` file.
//!
//! The card, right after GEOBEGIN, places a voxel structure: WHAT(1…3) its
//! lower corner, WHAT(4) a ROT-DEFI transformation (as for LATTICE, it
//! brings a point of the model into the voxel frame), SDUM the file name
//! (`.vxl` added). The file is Fortran unformatted sequential (each record
//! between two 4-byte lengths, in either byte order), as FLUKA's manual
//! writes it (program `writegolem`):
//!
//! 1. the title (80 characters);
//! 2. `NX, NY, NZ, NO, MO` (4-byte integers): voxels along x, y, z, the
//!    number of organs and the largest organ number;
//! 3. `DX, DY, DZ` (8-byte reals): the voxel size in cm;
//! 4. the organ of every voxel (2-byte integers, x fastest, then y, then z);
//! 5. for organs 1 to MO, their number after gaps in the numbering are
//!    removed (2-byte integers).
//!
//! FLUKA makes a body `VOXEL` of the whole structure (the user's regions
//! subtract it), a cage region `VOXEL` that contains the voxels, and one
//! region per organ, all after the user's regions: `VOXEL001` for organ 0
//! (the medium around the voxels), `VOXEL002` for the first organ after
//! renumbering, and so on; ASSIGNMA gives them materials. Here each organ
//! region is a union of RPP bodies: equal voxels are merged into runs along
//! x, runs into rectangles along y, and rectangles into boxes along z, so a
//! structure costs what its boundaries do, not its voxel count. The organ
//! regions fill the cage, so the cage region is not made (ASSIGNMA cards
//! naming it are accepted). Without the file the structure's size is
//! unknown: the body `VOXEL` is then empty (subtracting it takes nothing
//! away), the voxel regions are left out, and a warning says so.

use super::card::{self, Card};
use super::Reader;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use sv_geom::{Body, BodyKind, Op, Region, Term, Zone};
use sv_math::{DAffine3, DVec3};

/// Most voxels a `.vxl` file may hold (2 bytes each in memory).
pub const MAX_VOXELS: usize = 1 << 26;
/// Most boxes the merged voxels may make (each a body).
pub const MAX_VOXEL_BOXES: usize = 1_000_000;

/// The VOXELS card and, when its file was read, the voxels.
#[derive(Debug)]
pub(super) struct Voxels {
    /// The card's line.
    line: usize,
    /// The lower corner of the structure, in its own frame.
    origin: DVec3,
    /// The voxel frame to the model's coordinates.
    model_from_voxels: DAffine3,
    grid: Option<Grid>,
}

/// The contents of a `.vxl` file.
#[derive(Debug)]
struct Grid {
    counts: [usize; 3],
    size: DVec3,
    /// The region number (0 for the cage) of each voxel.
    regions: Vec<u16>,
}

/// A box of equal voxels: lower and upper voxel indices (upper exclusive)
/// and its region number.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
struct VoxelBox {
    lo: [u32; 3],
    hi: [u32; 3],
    region: u16,
}

/// The records of a Fortran unformatted sequential file (at most `limit`),
/// in either byte order; `None` when the lengths do not match up.
fn records(bytes: &[u8], limit: usize) -> Option<(Vec<&[u8]>, bool)> {
    [true, false].into_iter().find_map(|little| {
        let word = |at: usize| {
            let b: [u8; 4] = bytes.get(at..at + 4)?.try_into().ok()?;
            Some(if little {
                u32::from_le_bytes(b)
            } else {
                u32::from_be_bytes(b)
            } as usize)
        };
        let mut out = Vec::new();
        let mut at = 0;
        while out.len() < limit && at < bytes.len() {
            let n = word(at)?;
            let record = bytes.get(at + 4..(at + 4).checked_add(n)?)?;
            (word(at + 4 + n)? == n).then_some(())?;
            out.push(record);
            at += n + 8;
        }
        Some((out, little))
    })
}

/// Read the grid of a `.vxl` file's bytes.
fn parse_grid(bytes: &[u8]) -> Result<Grid, String> {
    let (recs, little) = records(bytes, 5)
        .ok_or("its record lengths do not match: not a Fortran unformatted file")?;
    if recs.len() < 4 {
        return Err(format!(
            "it holds {} records; a voxel file has 5",
            recs.len()
        ));
    }
    let int = |r: &[u8], k: usize| -> Option<i64> {
        let b: [u8; 4] = r.get(4 * k..4 * k + 4)?.try_into().ok()?;
        Some(i64::from(if little {
            i32::from_le_bytes(b)
        } else {
            i32::from_be_bytes(b)
        }))
    };
    let real = |r: &[u8], k: usize| -> Option<f64> {
        let b: [u8; 8] = r.get(8 * k..8 * k + 8)?.try_into().ok()?;
        Some(if little {
            f64::from_le_bytes(b)
        } else {
            f64::from_be_bytes(b)
        })
    };
    let short = |r: &[u8], k: usize| -> i16 {
        let b = [r[2 * k], r[2 * k + 1]];
        if little {
            i16::from_le_bytes(b)
        } else {
            i16::from_be_bytes(b)
        }
    };
    let head: Vec<i64> = (0..5).map_while(|k| int(recs[1], k)).collect();
    let [nx, ny, nz, _organs, max_organ] = head[..] else {
        return Err("record 2 does not hold NX, NY, NZ, NO, MO".into());
    };
    let counts = [nx, ny, nz].map(|n| usize::try_from(n).unwrap_or(0));
    let total = counts
        .iter()
        .try_fold(1usize, |a, &n| a.checked_mul(n))
        .unwrap_or(usize::MAX);
    if counts.contains(&0) || total > MAX_VOXELS {
        return Err(format!(
            "{nx} x {ny} x {nz} voxels: each count must be positive and the total at most \
             {MAX_VOXELS}"
        ));
    }
    let size: Vec<f64> = (0..3).map_while(|k| real(recs[2], k)).collect();
    if size.len() < 3 || !size.iter().all(|d| d.is_finite() && *d > 0.0) {
        return Err(format!(
            "record 3 must hold three positive voxel sizes DX, DY, DZ, found {size:?}"
        ));
    }
    if recs[3].len() != 2 * total {
        return Err(format!(
            "record 4 holds {} bytes; {total} voxels take {}",
            recs[3].len(),
            2 * total
        ));
    }
    // Organ numbers renumbered without gaps (record 5), where given.
    let max_organ = usize::try_from(max_organ)
        .unwrap_or(0)
        .min(i16::MAX as usize);
    let renumbered: Vec<u16> = match recs.get(4) {
        Some(r) if r.len() >= 2 * max_organ => (0..max_organ)
            .map(|k| u16::try_from(short(r, k)).unwrap_or(0))
            .collect(),
        _ => (1..=max_organ as u16).collect(),
    };
    let mut regions = Vec::with_capacity(total);
    for k in 0..total {
        let organ = short(recs[3], k);
        let region = match usize::try_from(organ) {
            Ok(0) => 0,
            Ok(o) => renumbered
                .get(o - 1)
                .copied()
                .filter(|r| *r > 0)
                .unwrap_or(o as u16),
            Err(_) => {
                return Err(format!(
                    "voxel {} has the negative organ number {organ}",
                    k + 1
                ))
            }
        };
        regions.push(region);
    }
    Ok(Grid {
        counts,
        size: DVec3::from_slice(&size),
        regions,
    })
}

/// Merge equal voxels into boxes: runs along x, rectangles of equal runs
/// along y, boxes of equal rectangles along z. `None` past `limit` boxes.
fn merge(grid: &Grid, limit: usize) -> Option<Vec<VoxelBox>> {
    let [nx, ny, nz] = grid.counts;
    type Rect = ([u32; 2], [u32; 2], u16);
    let mut boxes = Vec::new();
    let mut open_boxes: HashMap<Rect, u32> = HashMap::new();
    for z in 0..nz {
        let mut rects: Vec<Rect> = Vec::new();
        let mut open_rects: HashMap<([u32; 2], u16), u32> = HashMap::new();
        for y in 0..=ny {
            let mut row: HashMap<([u32; 2], u16), u32> = HashMap::new();
            if y < ny {
                let base = (z * ny + y) * nx;
                let mut x = 0;
                while x < nx {
                    let region = grid.regions[base + x];
                    let start = x;
                    while x < nx && grid.regions[base + x] == region {
                        x += 1;
                    }
                    let key = ([start as u32, x as u32], region);
                    let y0 = open_rects.remove(&key).unwrap_or(y as u32);
                    row.insert(key, y0);
                }
            }
            for ((xs, region), y0) in open_rects.drain() {
                rects.push((xs, [y0, y as u32], region));
            }
            open_rects = row;
        }
        let mut slab: HashMap<Rect, u32> = HashMap::with_capacity(rects.len());
        for rect in rects {
            let z0 = open_boxes.remove(&rect).unwrap_or(z as u32);
            slab.insert(rect, z0);
        }
        for ((xs, ys, region), z0) in open_boxes.drain() {
            boxes.push(VoxelBox {
                lo: [xs[0], ys[0], z0],
                hi: [xs[1], ys[1], z as u32],
                region,
            });
        }
        if boxes.len() + slab.len() > limit {
            return None;
        }
        open_boxes = slab;
    }
    for ((xs, ys, region), z0) in open_boxes {
        boxes.push(VoxelBox {
            lo: [xs[0], ys[0], z0],
            hi: [xs[1], ys[1], nz as u32],
            region,
        });
    }
    boxes.sort_unstable_by_key(|b| (b.region, b.lo[2], b.lo[1], b.lo[0]));
    Some(boxes)
}

/// The name FLUKA gives the region of the organs renumbered `n` (0 for
/// the organ-0 medium around the voxels): `VOXEL001` for organ 0,
/// `VOXEL002` for the first organ, and so on.
fn region_name(n: u16) -> String {
    format!("VOXEL{:03}", u32::from(n) + 1)
}

impl Reader {
    /// A VOXELS card: where the structure goes, and its file read.
    pub(super) fn voxels_card(&mut self, k: usize, c: &Card) {
        let what = |i: usize| {
            c.what[i]
                .as_ref()
                .and_then(|f| card::number(&f.text))
                .unwrap_or(0.0)
        };
        let origin = DVec3::new(what(0), what(1), what(2));
        let mut model_from_voxels = DAffine3::IDENTITY;
        if let Some(t) = c.what[3]
            .as_ref()
            .filter(|f| card::number(&f.text) != Some(0.0))
        {
            match self.find_transform(&t.text) {
                Some(xf) => model_from_voxels = xf.inverse(),
                None => {
                    let (col, len, text) = (t.col, t.len(), t.text.clone());
                    self.err(
                        k,
                        col,
                        len,
                        format!("VOXELS transformation `{text}` has no ROT-DEFI card"),
                    );
                }
            }
        }
        let mut voxels = Voxels {
            line: k,
            origin,
            model_from_voxels,
            grid: None,
        };
        let Some(f) = &c.sdum else {
            self.err(k, 1, 6, "VOXELS needs the name of its voxel file in SDUM")
                .hint = Some("FLUKA reads the voxels from SDUM.vxl beside the input".into());
            self.voxels = Some(voxels);
            return;
        };
        let (col, len) = (f.col, f.len());
        let name = if f.text.to_ascii_lowercase().ends_with(".vxl") {
            f.text.clone()
        } else {
            format!("{}.vxl", f.text)
        };
        let dir = Path::new(&self.out.files[self.lines[k].file].name)
            .parent()
            .map(Path::to_path_buf)
            .unwrap_or_default();
        let path: PathBuf = dir.join(&name);
        match std::fs::metadata(&path) {
            Err(_) => {
                let message = format!(
                    "voxel file `{}` not found: the voxel structure is left out \
                     (its size is in the file)",
                    path.display()
                );
                let hint = format!(
                    "put `{name}` beside the input to draw the voxels; meanwhile the body \
                     VOXEL is taken as empty and the regions VOXEL001… are not made"
                );
                self.warn_hinted(k, col, len, message, Some(hint));
            }
            Ok(m) if !m.is_file() || m.len() > (2 * MAX_VOXELS + 4096) as u64 => {
                let what = if m.is_file() {
                    format!("is larger than {MAX_VOXELS} voxels")
                } else {
                    "is not a regular file".to_string()
                };
                let message = format!("voxel file `{}` {what}", path.display());
                self.err(k, col, len, message);
            }
            Ok(_) => match std::fs::read(&path)
                .map_err(|e| e.to_string())
                .and_then(|b| parse_grid(&b))
            {
                Ok(grid) => voxels.grid = Some(grid),
                Err(e) => {
                    self.err(
                        k,
                        col,
                        len,
                        format!("cannot read the voxel file `{}`: {e}", path.display()),
                    );
                }
            },
        }
        self.voxels = Some(voxels);
    }

    /// The body VOXEL (the whole structure), or an empty one when the
    /// voxels are not known.
    pub(super) fn place_voxel_cage(&mut self) {
        let Some(v) = &self.voxels else {
            return;
        };
        let line = v.line;
        if self.body_index.contains_key("VOXEL") {
            let at = self.where_is(self.body_lines[self.body_index["VOXEL"]]);
            self.err(
                line,
                1,
                6,
                format!("the VOXELS card makes the body VOXEL, which is also defined on {at}"),
            );
            return;
        }
        let Some(grid) = &v.grid else {
            self.empty_bodies.insert("VOXEL".to_string());
            return;
        };
        let hi = v.origin
            + DVec3::new(
                grid.counts[0] as f64,
                grid.counts[1] as f64,
                grid.counts[2] as f64,
            ) * grid.size;
        let cage = Body::new(
            "VOXEL",
            BodyKind::Rpp,
            vec![v.origin.x, hi.x, v.origin.y, hi.y, v.origin.z, hi.z],
        );
        self.push_voxel_body(line, cage);
    }

    /// Add a body the voxels make, moved by the VOXELS transformation.
    fn push_voxel_body(&mut self, line: usize, body: Body) -> Option<usize> {
        let xf = self
            .voxels
            .as_ref()
            .map_or(DAffine3::IDENTITY, |v| v.model_from_voxels);
        let body = if xf == DAffine3::IDENTITY {
            body
        } else {
            match body.transformed(&xf) {
                Ok(b) => b,
                Err(e) => {
                    self.err(
                        line,
                        1,
                        6,
                        format!("cannot move the voxel body `{}`: {e}", body.name),
                    );
                    return None;
                }
            }
        };
        if self.body_index.contains_key(&body.name) {
            self.err(
                line,
                1,
                6,
                format!(
                    "the voxels make a body `{}`, a name the input already uses",
                    body.name
                ),
            );
            return None;
        }
        self.body_index.insert(body.name.clone(), self.bodies.len());
        self.bodies.push(body);
        self.body_lines.push(line);
        Some(self.bodies.len() - 1)
    }

    /// The regions VOXEL, VOXEL001… of the voxels, after the user's.
    pub(super) fn add_voxel_regions(&mut self) {
        let Some(v) = &self.voxels else {
            return;
        };
        let (line, origin) = (v.line, v.origin);
        let Some(grid) = &v.grid else {
            return;
        };
        let size = grid.size;
        let Some(boxes) = merge(grid, MAX_VOXEL_BOXES) else {
            self.err(
                line,
                1,
                6,
                format!("the voxels make more than {MAX_VOXEL_BOXES} boxes of equal voxels"),
            );
            return;
        };
        let mut zones: Vec<(u16, Vec<Zone>)> = Vec::new();
        for b in boxes {
            let lo = origin + DVec3::new(b.lo[0] as f64, b.lo[1] as f64, b.lo[2] as f64) * size;
            let hi = origin + DVec3::new(b.hi[0] as f64, b.hi[1] as f64, b.hi[2] as f64) * size;
            if zones.last().is_none_or(|(r, _)| *r != b.region) {
                zones.push((b.region, Vec::new()));
            }
            let count = zones.last().map_or(0, |(_, list)| list.len());
            let name = format!("{}_{}", region_name(b.region), count + 1);
            let body = Body::new(
                name,
                BodyKind::Rpp,
                vec![lo.x, hi.x, lo.y, hi.y, lo.z, hi.z],
            );
            let Some(index) = self.push_voxel_body(line, body) else {
                return;
            };
            if let Some((_, list)) = zones.last_mut() {
                list.push(Zone::new(vec![Term {
                    op: Op::Inside,
                    body: index,
                }]));
            }
        }
        for (region, list) in zones {
            let name = region_name(region);
            if self.region_index.contains_key(&name) {
                self.err(
                    line,
                    1,
                    6,
                    format!("the voxels make a region `{name}`, a name the input already uses"),
                );
                continue;
            }
            self.region_index.insert(name.clone(), self.regions.len());
            self.region_lines.push(line);
            self.regions.push(Region::new(name, list));
        }
    }

    /// Whether `name` is a voxel region this reader does not make: the
    /// cage region `VOXEL` (FLUKA's container of the organ regions, which
    /// fill it), and every voxel region when the file is missing. ASSIGNMA
    /// cards naming one are not reported.
    pub(super) fn is_unmade_voxel_region(&self, name: &str) -> bool {
        let Some(v) = &self.voxels else {
            return false;
        };
        name == "VOXEL"
            || (v.grid.is_none()
                && name
                    .strip_prefix("VOXEL")
                    .is_some_and(|n| n.bytes().all(|b| b.is_ascii_digit())))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(counts: [usize; 3], regions: Vec<u16>) -> Grid {
        Grid {
            counts,
            size: DVec3::ONE,
            regions,
        }
    }

    #[test]
    fn equal_voxels_merge_into_boxes() {
        // 4 x 2 x 2: region 1 fills x < 2 everywhere, region 0 the rest.
        let r: Vec<u16> = (0..16).map(|k| u16::from(k % 4 < 2)).collect();
        let boxes = merge(&grid([4, 2, 2], r), 100).unwrap();
        assert_eq!(
            boxes,
            [
                VoxelBox {
                    lo: [2, 0, 0],
                    hi: [4, 2, 2],
                    region: 0
                },
                VoxelBox {
                    lo: [0, 0, 0],
                    hi: [2, 2, 2],
                    region: 1
                },
            ]
        );
        // A checkerboard does not merge, and the limit holds.
        let r: Vec<u16> = (0..8).map(|k| ((k + k / 2 + k / 4) % 2) as u16).collect();
        assert_eq!(merge(&grid([2, 2, 2], r.clone()), 100).unwrap().len(), 8);
        assert!(merge(&grid([2, 2, 2], r), 7).is_none());
    }

    fn record(out: &mut Vec<u8>, bytes: &[u8], little: bool) {
        let n = bytes.len() as u32;
        let n = if little {
            n.to_le_bytes()
        } else {
            n.to_be_bytes()
        };
        out.extend(n);
        out.extend(bytes);
        out.extend(n);
    }

    /// Values as bytes in the byte order asked for.
    macro_rules! encoded {
        ($values:expr, $little:expr) => {
            $values
                .iter()
                .flat_map(|v| {
                    if $little {
                        v.to_le_bytes()
                    } else {
                        v.to_be_bytes()
                    }
                })
                .collect::<Vec<u8>>()
        };
    }

    #[test]
    fn a_vxl_file_in_either_byte_order() {
        for little in [true, false] {
            let mut f = Vec::new();
            record(&mut f, &[b' '; 80], little);
            record(&mut f, &encoded!([2i32, 1, 1, 1, 7], little), little);
            record(&mut f, &encoded!([0.5f64, 1.0, 2.0], little), little);
            record(&mut f, &encoded!([0i16, 7], little), little);
            record(&mut f, &encoded!([0i16, 0, 0, 0, 0, 0, 1], little), little);
            let g = parse_grid(&f).unwrap();
            assert_eq!(g.counts, [2, 1, 1]);
            assert_eq!(g.size, DVec3::new(0.5, 1.0, 2.0));
            assert_eq!(g.regions, [0, 1]);
        }
        assert!(parse_grid(&[1, 2, 3])
            .unwrap_err()
            .contains("record lengths"));
    }
}
