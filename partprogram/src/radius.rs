//! Tool radius compensation G40/G41/G42 applied to the planned path, shared by both dialects.
//!
//! The executors hand every canonical block to a [`Compensator`] together with a [`Ctx`] (the modal
//! side, the radius of the active correction entry, the compensation plane and the block's location).
//! The compensator holds back the last motion in the plane until the next one is known (one element of
//! look-ahead; blocks in between are queued and keep their order), then replaces the plane coordinates
//! of its end point by the compensated ones (structure spec §13.3–13.4):
//!
//! * start-up: the first motion in the plane with G41/G42 active (linear only) ends on the perpendicular
//!   to the start of the next motion, so the next block runs fully compensated;
//! * corners: a tangent join takes the perpendicular point; an outside corner gets an arc about the
//!   programmed corner ([`Corners::Arc`], MC 339 decade 8 = 1, the default) or the intersection of the
//!   equidistants ([`Corners::Intersection`]); an inside corner always takes the intersection;
//! * cancel: the last motion before G40 ends on the perpendicular at its end; the G40 motion (linear
//!   only) goes to its programmed end point;
//! * a change of side, radius or correction entry while active works as a cancel followed by a
//!   start-up on the next motion;
//! * compensated arcs keep their centre; their feed becomes `F·R'/R` (§13.6) unless disabled;
//! * interference: a fully compensated element (not the start-up line) that runs backwards, collapses
//!   or whose arc sweep reverses is error 2512 at its block ([`gouge`]).

pub mod gouge;
pub mod offset;

use crate::canon::{Canon, Kind};
use crate::codes;
use crate::run::RunError;
use offset::{Geo, Joint, V2, corner};

/// How outside corners are joined (machine constant 339, decade 8).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Corners {
    /// Insert an arc about the programmed corner (decade 8 = 1; recommended by the manual).
    #[default]
    Arc,
    /// End points at the intersection of the equidistants (decade 8 = 0).
    Intersection,
}

impl std::str::FromStr for Corners {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.to_ascii_lowercase().as_str() {
            "arc" => Ok(Corners::Arc),
            "intersection" => Ok(Corners::Intersection),
            other => Err(format!(
                "unknown corner mode `{other}` (use arc or intersection)"
            )),
        }
    }
}

/// Settings of radius compensation (machine constants 339 and R168).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RadiusOptions {
    /// Outside-corner mode.
    pub corners: Corners,
    /// Limit angle in degrees (MC 339 decades 1–6): arcs are inserted only above it.
    pub arc_limit_deg: f64,
    /// Feed on compensated arcs `F·R'/R` (constant speed at the contact point); false as MC R168 d5 = 1.
    pub adapt_arc_feed: bool,
}

impl Default for RadiusOptions {
    fn default() -> Self {
        RadiusOptions {
            corners: Corners::Arc,
            arc_limit_deg: 0.0,
            adapt_arc_feed: true,
        }
    }
}

/// Compensation side selected by G40/G41/G42.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Side {
    /// G40: no compensation.
    #[default]
    Off,
    /// G41: tool centre left of the programmed direction.
    Left,
    /// G42: tool centre right of the programmed direction.
    Right,
}

impl Side {
    /// The side of G function 40, 41 or 42 (anything else: off).
    pub fn from_g(g: u16) -> Side {
        match g {
            41 => Side::Left,
            42 => Side::Right,
            _ => Side::Off,
        }
    }
}

/// What the executor knows about a canonical block when it emits it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ctx {
    /// Modal side.
    pub side: Side,
    /// Radius of the active correction entry (mm; negative swaps the side; 0 for D0).
    pub radius: f64,
    /// The compensation plane's (first, second) axis letters.
    pub axes: (char, char),
    /// Factor from the canonical coordinate to true mm per plane axis (0.5 for a diameter X).
    pub scale: (f64, f64),
    /// Exactly one plane axis is mirrored: the side flips in the machine frame.
    pub mirrored: bool,
    /// File index of the block.
    pub file: usize,
    /// Byte range of the block.
    pub span: (usize, usize),
}

impl Ctx {
    /// Signed offset in the machine frame (positive: left), None when compensation is off.
    fn active(&self) -> Option<Active> {
        let sign = match self.side {
            Side::Off => return None,
            Side::Left => 1.0,
            Side::Right => -1.0,
        };
        let sign = if self.mirrored { -sign } else { sign };
        Some(Active {
            d: sign * self.radius,
            axes: self.axes,
            scale: self.scale,
        })
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
struct Active {
    d: f64,
    axes: (char, char),
    scale: (f64, f64),
}

#[derive(Debug)]
struct Pending {
    canon: Canon,
    geo: Geo,
    active: Active,
    startup: bool,
    /// Compensated start point (None for the start-up line, which starts at the programmed point).
    from: Option<V2>,
    file: usize,
    span: (usize, usize),
}

/// The radius-compensation stage between an executor and its output (one element of look-ahead).
#[derive(Debug, Default)]
pub struct Compensator {
    opts: RadiusOptions,
    prev: Vec<(char, f64)>,
    start: Vec<(char, f64)>,
    pending: Option<Pending>,
    /// Compensated start of the element after the last released one.
    next_from: Option<V2>,
    queue: Vec<Canon>,
    error: Option<RunError>,
}

fn coord(list: &[(char, f64)], a: char) -> Option<f64> {
    list.iter().find(|(c, _)| *c == a).map(|(_, v)| *v)
}

fn point(list: &[(char, f64)], axes: (char, char), scale: (f64, f64)) -> Option<V2> {
    Some(V2::new(
        coord(list, axes.0)? * scale.0,
        coord(list, axes.1)? * scale.1,
    ))
}

fn set_point(list: &mut [(char, f64)], a: &Active, p: V2) {
    for (c, v) in list.iter_mut() {
        if *c == a.axes.0 {
            *v = p.x / a.scale.0;
        } else if *c == a.axes.1 {
            *v = p.y / a.scale.1;
        }
    }
}

fn block_name(c: &Canon) -> String {
    c.n.map_or_else(|| "the block".to_string(), |n| format!("N{n}"))
}

impl Compensator {
    /// A compensator with the given settings, compensation off.
    pub fn new(opts: RadiusOptions) -> Self {
        Compensator {
            opts,
            ..Compensator::default()
        }
    }

    /// Returns the first error found so far (the blocks after it are dropped).
    pub fn check(&mut self) -> Result<(), RunError> {
        match self.error.take() {
            Some(e) => Err(e),
            None => Ok(()),
        }
    }

    fn fail(&mut self, file: usize, span: (usize, usize), code: u32, message: String) {
        if self.error.is_none() {
            self.error = Some(RunError {
                code,
                message,
                file,
                span,
            });
        }
        self.pending = None;
        self.queue.clear();
    }

    /// The element a canonical block describes in the plane, if it moves in the plane.
    fn element(
        start: &[(char, f64)],
        c: &Canon,
        axes: (char, char),
        scale: (f64, f64),
    ) -> Option<Geo> {
        let a = V2::new(
            coord(start, axes.0).unwrap_or(0.0) * scale.0,
            coord(start, axes.1).unwrap_or(0.0) * scale.1,
        );
        let b = point(&c.end, axes, scale)?;
        match c.kind {
            Kind::Rapid | Kind::Linear if (b - a).len() > 1e-9 => Some(Geo::Line { a, b }),
            Kind::ArcCw | Kind::ArcCcw => Some(Geo::Arc {
                a,
                b,
                c: point(&c.center, axes, scale)?,
                ccw: c.kind == Kind::ArcCcw,
            }),
            _ => None,
        }
    }

    /// Takes the next canonical block of the executor; finished blocks are appended to `out`.
    pub fn push(&mut self, c: Canon, ctx: &Ctx, out: &mut Vec<Canon>) {
        if self.error.is_some() {
            return;
        }
        // The programmed start is the previous block's programmed end (buffers reused, no allocation).
        std::mem::swap(&mut self.start, &mut self.prev);
        self.prev.clone_from(&c.end);
        if self.pending.is_none() && ctx.side == Side::Off {
            out.push(c);
            return;
        }
        let want = ctx.active();
        if let (Some(p), Some(w)) = (&self.pending, want)
            && p.active.axes != w.axes
        {
            let msg = format!(
                "radius compensation: the plane changed from {}{} to {}{} while G41/G42 is active",
                p.active.axes.0, p.active.axes.1, w.axes.0, w.axes.1
            );
            self.fail(ctx.file, ctx.span, codes::RUN_COMP_RULE, msg);
            return;
        }
        let geo = match &self.pending {
            Some(p) => Self::element(&self.start, &c, p.active.axes, p.active.scale),
            None => Self::element(&self.start, &c, ctx.axes, ctx.scale),
        };
        let Some(geo) = geo else {
            if self.pending.is_some() {
                self.queue.push(c);
            } else {
                out.push(c);
            }
            return;
        };
        let held = self.pending.take();
        let cancels = held.is_some() && want.is_none();
        let continues = held.as_ref().is_some_and(|p| Some(p.active) == want);
        if let Some(p) = held {
            let d = p.active.d;
            let joint = if !continues {
                Ok(Joint::Point(p.geo.end_offset(d)))
            } else if p.startup {
                Ok(Joint::Point(geo.start_offset(d)))
            } else {
                let insert = self.opts.corners == Corners::Arc;
                corner(
                    &p.geo,
                    &geo,
                    d,
                    insert,
                    self.opts.arc_limit_deg.to_radians(),
                )
            };
            match joint {
                Ok(j) => {
                    if self.interferes(&p, j, Some(&c)) {
                        return;
                    }
                    self.release(p, j, &c, out)
                }
                Err(e) => {
                    let msg = format!(
                        "radius compensation: {e} between {} and {}",
                        block_name(&p.canon),
                        block_name(&c)
                    );
                    self.fail(p.file, p.span, codes::RUN_EQUIDISTANT, msg);
                    return;
                }
            }
        }
        let Some(a) = want else {
            if cancels && matches!(geo, Geo::Arc { .. }) {
                let msg = "radius compensation can be switched off (G40) only in a linear block";
                self.fail(ctx.file, ctx.span, codes::RUN_COMP_RULE, msg.to_string());
                return;
            }
            out.push(c);
            return;
        };
        if !continues && matches!(geo, Geo::Arc { .. }) {
            let msg = "radius compensation can be switched on (G41/G42) only in a linear block";
            self.fail(ctx.file, ctx.span, codes::RUN_COMP_RULE, msg.to_string());
            return;
        }
        if let Some((r, rd)) = geo.offset_radius(a.d)
            && a.d != 0.0
            && rd <= 1e-9
        {
            let msg = format!(
                "radius compensation: the arc radius {r:.4} of {} is smaller than the tool radius {:.4} on its inside",
                block_name(&c),
                a.d.abs()
            );
            self.fail(ctx.file, ctx.span, codes::RUN_EQUIDISTANT, msg);
            return;
        }
        self.pending = Some(Pending {
            canon: c,
            geo,
            active: a,
            startup: !continues,
            from: if continues { self.next_from } else { None },
            file: ctx.file,
            span: ctx.span,
        });
    }

    /// The interference check of the held element `p` ending at `joint` (the start-up line and radius 0
    /// are not checked); records error 2512 located at `p` and returns true when it would gouge.
    fn interferes(&mut self, p: &Pending, joint: Joint, next: Option<&Canon>) -> bool {
        let Some(from) = p.from.filter(|_| !p.startup && p.active.d != 0.0) else {
            return false;
        };
        let to = match joint {
            Joint::Point(q) => q,
            Joint::Arc { a, .. } => a,
        };
        let Some(g) = gouge::check(&p.geo, from, to) else {
            return false;
        };
        let (ax, s) = (p.active.axes, p.active.scale);
        let at = |v: V2| format!("{}{:.4} {}{:.4}", ax.0, v.x / s.0, ax.1, v.y / s.1);
        let what = if matches!(p.geo, Geo::Line { .. }) {
            "line"
        } else {
            "arc"
        };
        let after = next.map_or_else(
            || " at the end of the program".to_string(),
            |n| format!(" before {}", block_name(n)),
        );
        let msg = format!(
            "radius compensation: interference (gouge) at {}: the compensated {what} from {} to {} {g}{after}; the tool radius {:.4} does not fit",
            block_name(&p.canon),
            at(from),
            at(to),
            p.active.d.abs()
        );
        self.fail(p.file, p.span, codes::RUN_GOUGE, msg);
        true
    }

    /// Emits the held element `p` ending at the joint, the blocks queued behind it, and an inserted
    /// corner arc (built on the template `next`).
    fn release(&mut self, p: Pending, joint: Joint, next: &Canon, out: &mut Vec<Canon>) {
        let end = match joint {
            Joint::Point(q) => q,
            Joint::Arc { a, .. } => a,
        };
        self.next_from = Some(match joint {
            Joint::Point(q) => q,
            Joint::Arc { b, .. } => b,
        });
        let mut c = p.canon;
        set_point(&mut c.end, &p.active, end);
        if self.opts.adapt_arc_feed
            && let Some((r, rd)) = p.geo.offset_radius(p.active.d)
            && r > 1e-9
        {
            c.feed = c.feed.map(|f| f * (rd / r));
        }
        out.push(c);
        for mut q in self.queue.drain(..) {
            set_point(&mut q.end, &p.active, end);
            out.push(q);
        }
        if let Joint::Arc { a: _, b, ccw } = joint {
            let corner = p.geo.end();
            let base = out
                .last()
                .map_or_else(|| next.end.clone(), |l| l.end.clone());
            let mut arc = next.clone();
            arc.kind = if ccw { Kind::ArcCcw } else { Kind::ArcCw };
            arc.end = base;
            set_point(&mut arc.end, &p.active, b);
            let (ax, s) = (p.active.axes, p.active.scale);
            arc.center = vec![(ax.0, corner.x / s.0), (ax.1, corner.y / s.1)];
            arc.m = Vec::new();
            arc.dwell = None;
            arc.thread = false;
            out.push(arc);
        }
    }

    /// Ends the program: the held element ends on the perpendicular at its end point, then the queued
    /// blocks follow. Returns the first error found.
    pub fn finish(&mut self, out: &mut Vec<Canon>) -> Result<(), RunError> {
        self.check()?;
        if let Some(p) = self.pending.take() {
            let end = p.geo.end_offset(p.active.d);
            if self.interferes(&p, Joint::Point(end), None) {
                return self.check();
            }
            let next = p.canon.clone();
            self.release(p, Joint::Point(end), &next, out);
        }
        out.append(&mut self.queue);
        Ok(())
    }
}
