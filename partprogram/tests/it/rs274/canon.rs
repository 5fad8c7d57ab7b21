//! Converter of LinuxCNC `rs274 -g` canonical output to plan records in the machine frame, the same
//! records taken from our canonical blocks, and their comparison block by block.
//!
//! rs274 prints positions in the frame of the active G5x + G92 offsets without the tool length
//! offset: machine = position + G5x + G92 + tool offset (`SET_G5X_OFFSET`, `SET_G92_OFFSET`,
//! `USE_TOOL_LENGTH_OFFSET`, all in mm here). Arcs are `ARC_FEED(first end, second end, first
//! centre, second centre, rotation, third-axis end, …)` with the plane's axis order XY, ZX, YZ
//! (rotation < 0 clockwise).

use partprogram::{Canon, Kind};

/// Motion kinds compared.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mk {
    /// Rapid.
    Rapid,
    /// Feed line.
    Line,
    /// Clockwise arc.
    Cw,
    /// Counter-clockwise arc.
    Ccw,
}

/// One motion record: block number, kind, machine end (X, Y, Z), arc centre (the plane pair, machine).
#[derive(Debug, Clone, PartialEq)]
pub struct Rec {
    /// N of the source block.
    pub n: u32,
    /// Kind.
    pub kind: Mk,
    /// End X, Y, Z.
    pub end: [f64; 3],
    /// Arc centre (two plane coordinates), empty for lines.
    pub centre: Vec<f64>,
}

fn args(line: &str, name: &str) -> Option<Vec<f64>> {
    let at = line.find(name)?;
    let rest = &line[at + name.len()..];
    let inner = rest.strip_prefix('(')?.split(')').next()?;
    Some(
        inner
            .split([',', ' '])
            .filter(|s| !s.is_empty())
            .filter_map(|s| s.parse().ok())
            .collect(),
    )
}

fn n_of(line: &str) -> u32 {
    line.split_whitespace()
        .nth(1)
        .and_then(|t| t.strip_prefix('N'))
        .and_then(|t| t.parse().ok())
        .unwrap_or(0)
}

/// Converts rs274 canonical output; Err with rs274's error text when it stopped on an error.
pub fn from_rs274(out: &str) -> Result<Vec<Rec>, String> {
    let (mut g5x, mut g92, mut tlo) = ([0.0; 3], [0.0; 3], [0.0; 3]);
    let mut plane = 0;
    let mut recs = Vec::new();
    for line in out.lines() {
        let t = line.trim_start();
        if !t.chars().next().is_some_and(|c| c.is_ascii_digit()) {
            if !t.is_empty() && t != "executing" {
                return Err(t.to_string());
            }
            continue;
        }
        let origin = |i: usize| g5x[i] + g92[i] + tlo[i];
        if let Some(a) = args(t, "SET_G5X_OFFSET") {
            g5x = [a[1], a[2], a[3]];
        } else if let Some(a) = args(t, "SET_G92_OFFSET") {
            g92 = [a[0], a[1], a[2]];
        } else if let Some(a) = args(t, "USE_TOOL_LENGTH_OFFSET") {
            tlo = [a[0], a[1], a[2]];
        } else if t.contains("SELECT_PLANE(CANON_PLANE_XY)") {
            plane = 0;
        } else if t.contains("SELECT_PLANE(CANON_PLANE_XZ)") {
            plane = 1;
        } else if t.contains("SELECT_PLANE(CANON_PLANE_YZ)") {
            plane = 2;
        } else if let Some(a) = args(t, "STRAIGHT_TRAVERSE").or_else(|| args(t, "STRAIGHT_FEED")) {
            let kind = if t.contains("TRAVERSE") {
                Mk::Rapid
            } else {
                Mk::Line
            };
            recs.push(Rec {
                n: n_of(line),
                kind,
                end: [a[0] + origin(0), a[1] + origin(1), a[2] + origin(2)],
                centre: Vec::new(),
            });
        } else if let Some(a) = args(t, "ARC_FEED") {
            // (first, second, third) axis indices of the plane.
            let (f, s, th) = match plane {
                0 => (0, 1, 2),
                1 => (2, 0, 1),
                _ => (1, 2, 0),
            };
            let mut end = [0.0; 3];
            end[f] = a[0] + origin(f);
            end[s] = a[1] + origin(s);
            end[th] = a[5] + origin(th);
            recs.push(Rec {
                n: n_of(line),
                kind: if a[4] < 0.0 { Mk::Cw } else { Mk::Ccw },
                end,
                centre: vec![a[2] + origin(f), a[3] + origin(s)],
            });
        }
    }
    Ok(recs)
}

/// The same records from our plan.
pub fn from_plan(blocks: &[Canon]) -> Vec<Rec> {
    blocks
        .iter()
        .filter_map(|c| {
            let kind = match c.kind {
                Kind::Rapid => Mk::Rapid,
                Kind::Linear => Mk::Line,
                Kind::ArcCw => Mk::Cw,
                Kind::ArcCcw => Mk::Ccw,
                _ => return None,
            };
            let e = |a| c.end_of(a).unwrap_or(0.0);
            Some(Rec {
                n: c.n.unwrap_or(0),
                kind,
                end: [e('X'), e('Y'), e('Z')],
                centre: c.center.iter().map(|(_, v)| *v).collect(),
            })
        })
        .collect()
}

/// Drops moves that end where the previous move ended (rs274 and we differ in emitting them).
pub fn moving(recs: Vec<Rec>) -> Vec<Rec> {
    let mut out: Vec<Rec> = Vec::with_capacity(recs.len());
    let mut at = [0.0; 3];
    for r in recs {
        let same = r.end.iter().zip(at).all(|(a, b)| (a - b).abs() < 1e-6);
        at = r.end;
        if same && matches!(r.kind, Mk::Rapid | Mk::Line) {
            continue;
        }
        out.push(r);
    }
    out
}

/// Keeps of each block in `peck` (one G73/G83 hole, whose peck retract amounts differ by intent) the
/// rapid moves before the first feed, the deepest feed and the final retract. Apply after
/// [`moving`].
pub fn project_pecks(recs: Vec<Rec>, peck: &[u32]) -> Vec<Rec> {
    let mut out: Vec<Rec> = Vec::new();
    let mut i = 0;
    while i < recs.len() {
        let n = recs[i].n;
        let mut j = i;
        while j < recs.len() && recs[j].n == n {
            j += 1;
        }
        let group = &recs[i..j];
        if peck.contains(&n) {
            let first_feed = group.iter().position(|r| r.kind == Mk::Line).unwrap_or(0);
            out.extend(group[..first_feed].iter().cloned());
            let deep = group
                .iter()
                .filter(|r| r.kind == Mk::Line)
                .min_by(|a, b| a.end[2].total_cmp(&b.end[2]));
            out.extend(deep.cloned());
            out.extend(group.last().cloned());
        } else {
            out.extend(group.iter().cloned());
        }
        i = j;
    }
    out
}

/// The first difference of two record lists within `tol` mm, None when they agree.
pub fn diff(ours: &[Rec], theirs: &[Rec], tol: f64) -> Option<String> {
    for (i, (a, b)) in ours.iter().zip(theirs).enumerate() {
        let close = |x: &[f64], y: &[f64]| {
            x.len() == y.len() && x.iter().zip(y).all(|(p, q)| (p - q).abs() <= tol)
        };
        if a.kind != b.kind || !close(&a.end, &b.end) || !close(&a.centre, &b.centre) {
            return Some(format!("record {i}: ours {a:?}, rs274 {b:?}"));
        }
    }
    if ours.len() != theirs.len() {
        return Some(format!(
            "{} records ours, {} rs274 (first extra: {:?})",
            ours.len(),
            theirs.len(),
            ours.get(theirs.len()).or(theirs.get(ours.len()))
        ));
    }
    None
}
