//! Canonical blocks: what the planner emits for every executed block — motion with its resolved end
//! point, arc centre and plane in the machine frame, feed, spindle, tool, dwell and M functions.

use std::fmt::Write as _;

/// Kind of canonical block.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Kind {
    /// G00 positioning at rapid traverse.
    Rapid,
    /// G01 linear interpolation (also G33 threads, with `thread` set).
    Linear,
    /// Clockwise arc.
    ArcCw,
    /// Counter-clockwise arc.
    ArcCcw,
    /// Dwell.
    Dwell,
    /// Auxiliary functions only (M, S, T) without motion.
    Aux,
}

impl Kind {
    /// The JSON name.
    pub fn name(self) -> &'static str {
        match self {
            Kind::Rapid => "rapid",
            Kind::Linear => "linear",
            Kind::ArcCw => "arc_cw",
            Kind::ArcCcw => "arc_ccw",
            Kind::Dwell => "dwell",
            Kind::Aux => "aux",
        }
    }
}

/// Interpolation plane.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum Plane {
    /// G17.
    XY,
    /// G18.
    ZX,
    /// G19.
    YZ,
    /// MEFI G14, G15, G16: a plane of machine constant 341 with the 4th axis.
    Extra {
        /// The G function (14, 15 or 16).
        g: u8,
        /// First axis letter (I runs along it).
        first: char,
        /// Second axis letter (J runs along it).
        second: char,
    },
}

impl Plane {
    /// The JSON name: the first and second axis letters (`XY`, `ZX`, `YZ`, or e.g. `ZA` under G14).
    pub fn name(self) -> String {
        let (a, b) = self.axes();
        format!("{a}{b}")
    }

    /// The (first, second) axis letters of the plane; I runs along the first, J along the second.
    pub fn axes(self) -> (char, char) {
        match self {
            Plane::XY => ('X', 'Y'),
            Plane::ZX => ('Z', 'X'),
            Plane::YZ => ('Y', 'Z'),
            Plane::Extra { first, second, .. } => (first, second),
        }
    }

    /// The G function that selects the plane (17, 18, 19, or 14–16).
    pub fn g(self) -> u16 {
        match self {
            Plane::XY => 17,
            Plane::ZX => 18,
            Plane::YZ => 19,
            Plane::Extra { g, .. } => u16::from(g),
        }
    }
}

/// An M function with its timing relative to the block's motion.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct MFunc {
    /// M number.
    pub m: u16,
    /// True when executed before the motion (IOCFIL m_type bit 0).
    pub before: bool,
}

/// One canonical block.
#[derive(Debug, Clone, PartialEq)]
pub struct Canon {
    /// Block number of the source block (None for Fanuc blocks without N).
    pub n: Option<u32>,
    /// The unit the block belongs to when not the main program (`"L81"`, `"sub100"`).
    pub unit: Option<String>,
    /// What the block does.
    pub kind: Kind,
    /// End position per machine axis (axis letter, mm), machine frame, all axes.
    pub end: Vec<(char, f64)>,
    /// Arc centre (two plane axes), machine frame.
    pub center: Vec<(char, f64)>,
    /// Interpolation plane.
    pub plane: Plane,
    /// Feed in mm/min (None for rapid and non-motion blocks, or per-revolution feed without S).
    pub feed: Option<f64>,
    /// M functions of the block, before-motion ones first.
    pub m: Vec<MFunc>,
    /// Spindle speed (modal).
    pub s: Option<f64>,
    /// Tool (modal).
    pub t: Option<i64>,
    /// Dwell in seconds (kind dwell).
    pub dwell: Option<f64>,
    /// True for a G33 thread block.
    pub thread: bool,
    /// G33: the start angle after the spindle's zero pulse, degrees (MEFI `I`; 0: at the pulse).
    pub thread_angle: f64,
    /// True when the motion stops exactly at the block's end point before the next block starts:
    /// Fanuc G09 (this block) or G61 (modal); MEFI G98 (standard block connection) or G24 (firm
    /// connection), false under MEFI G23 (smooth connection) and Fanuc G64.
    pub exact_stop: bool,
    /// Path blending tolerance in mm set by Fanuc `G64 P<tol>` (None: the machine's default).
    pub tolerance: Option<f64>,
    /// Constant surface speed (MEFI KŘR G96/G97, Fanuc G96) active in this block.
    pub css: Option<Css>,
    /// F was programmed under G94 (feed per minute without KŘR; always for Fanuc): the PLC's
    /// QCKFD may replace it with the alternative feed PGCFIL QFD.
    pub feed_g94: bool,
    /// The modal state the block ran under that its resolved positions no longer show.
    pub modal: BlockModal,
}

/// The modal state a block runs under that its resolved (absolute, offset, compensated)
/// positions no longer show: distance and feed mode, work offset, cutter compensation and tool
/// length. For displays (the HMI's modal codes, `nc plan`'s `modal`); nothing plans with it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BlockModal {
    /// G90 (absolute) or G91 (incremental).
    pub distance: u8,
    /// G94 (mm/min) or G95 (mm/rev); MEFI also G96 and G97 (KŘR with feed per minute or per
    /// revolution).
    pub feed_mode: u8,
    /// The work offset's G code (MEFI G53–G57, Fanuc G54–G59 or 154 with `work_p`); 0: none.
    pub work: u8,
    /// Fanuc `G154 P<n>` (also G110–G129 and `G54.1 P`): n; 0 otherwise.
    pub work_p: u8,
    /// Cutter compensation: G40, G41 or G42.
    pub cutter: u8,
    /// The D register in effect (0: none).
    pub d: i64,
    /// Tool length compensation (Fanuc): G43, G44 or G49; 0 in MEFI (lengths come with D).
    pub length: u8,
    /// The H register of G43/G44 (0: none).
    pub h: i64,
    /// Contour control for short blocks (the motion kernel's tolerance-band smoothing and
    /// complex speed): Fanuc `G05.1 Q1` / `G08 P1` until `Q0` / `P0`, MEFI `G23`.
    pub contour: bool,
}

impl Default for BlockModal {
    /// G90, G94, no work offset, G40, no D, no tool length (blocks the kernel makes itself).
    fn default() -> Self {
        BlockModal {
            distance: 90,
            feed_mode: 94,
            work: 0,
            work_p: 0,
            cutter: 40,
            d: 0,
            length: 0,
            h: 0,
            contour: false,
        }
    }
}

impl BlockModal {
    /// The codes as displays show them: `["G90", "G94", "G54", "G41", "D1", "G43", "H2"]` (D
    /// when not 0 — MEFI's D also selects the lengths —, H only under G43/G44, the work offset
    /// and the tool length only when there are any).
    pub fn codes(&self) -> Vec<String> {
        let mut v = vec![
            format!("G{}", self.distance),
            format!("G{}", self.feed_mode),
        ];
        match (self.work, self.work_p) {
            (0, _) => {}
            (g, 0) => v.push(format!("G{g}")),
            (g, p) => v.push(format!("G{g} P{p}")),
        }
        v.push(format!("G{}", self.cutter));
        if self.d != 0 {
            v.push(format!("D{}", self.d));
        }
        if self.length != 0 {
            v.push(format!("G{}", self.length));
        }
        if self.h != 0 && matches!(self.length, 43 | 44) {
            v.push(format!("H{}", self.h));
        }
        v
    }
}

/// Constant surface speed: the kernel computes the spindle speed from the radius every tick.
#[derive(Debug, Clone, PartialEq)]
pub struct Css {
    /// Cutting speed in m/min.
    pub m_min: f64,
    /// Top spindle speed (rev/min) set by Fanuc `G50 S` (None: the gear range's limit).
    pub max_rpm: Option<f64>,
    /// Machine-frame position of the program zero of every axis (the rotation axis lies on the
    /// controlling axis's zero).
    pub origin: Vec<(char, f64)>,
    /// X is programmed as a diameter (the radius is half the distance from the zero).
    pub diameter: bool,
}

impl Css {
    /// Spindle speed (rev/min) for the controlling axis `axis` at machine position `pos`, before
    /// the top-speed clamp: v·1000 / (2π·r); `f64::INFINITY` on the rotation axis.
    pub fn rpm_at(&self, axis: char, pos: f64) -> f64 {
        let zero = self
            .origin
            .iter()
            .find(|(c, _)| *c == axis)
            .map_or(0.0, |(_, v)| *v);
        let mut r = (pos - zero).abs();
        if self.diameter && axis == 'X' {
            r /= 2.0;
        }
        if r == 0.0 {
            return f64::INFINITY;
        }
        self.m_min * 1000.0 / (2.0 * std::f64::consts::PI * r)
    }
}

/// Formats a coordinate: rounded to 1 nm, shortest decimal form, no `-0`.
pub fn num(v: f64) -> String {
    let r = (v * 1_000_000.0).round() / 1_000_000.0;
    let r = if r == 0.0 { 0.0 } else { r };
    format!("{r}")
}

impl Canon {
    /// The one-line JSON form written by `ncplc nc plan --format json`.
    pub fn to_json_line(&self) -> String {
        let mut s = String::with_capacity(160);
        s.push_str("{\"n\":");
        match self.n {
            Some(n) => {
                let _ = write!(s, "{n}");
            }
            None => s.push_str("null"),
        }
        if let Some(u) = &self.unit {
            let _ = write!(s, ",\"unit\":\"{u}\"");
        }
        let _ = write!(s, ",\"kind\":\"{}\",\"end\":{{", self.kind.name());
        for (i, (a, v)) in self.end.iter().enumerate() {
            let _ = write!(s, "{}\"{a}\":{}", if i > 0 { "," } else { "" }, num(*v));
        }
        s.push('}');
        if !self.center.is_empty() {
            s.push_str(",\"center\":{");
            for (i, (a, v)) in self.center.iter().enumerate() {
                let _ = write!(s, "{}\"{a}\":{}", if i > 0 { "," } else { "" }, num(*v));
            }
            s.push('}');
        }
        let (p1, p2) = self.plane.axes();
        let _ = write!(s, ",\"plane\":\"{p1}{p2}\"");
        match self.feed {
            Some(f) => {
                let _ = write!(s, ",\"feed\":{}", num(f));
            }
            None => s.push_str(",\"feed\":null"),
        }
        s.push_str(",\"m\":[");
        for (i, m) in self.m.iter().enumerate() {
            let _ = write!(s, "{}{}", if i > 0 { "," } else { "" }, m.m);
        }
        s.push_str("],\"m_timing\":[");
        for (i, m) in self.m.iter().enumerate() {
            let _ = write!(
                s,
                "{}\"{}\"",
                if i > 0 { "," } else { "" },
                if m.before { "before" } else { "after" }
            );
        }
        s.push(']');
        match self.s {
            Some(v) => {
                let _ = write!(s, ",\"s\":{}", num(v));
            }
            None => s.push_str(",\"s\":null"),
        }
        match self.t {
            Some(v) => {
                let _ = write!(s, ",\"t\":{v}");
            }
            None => s.push_str(",\"t\":null"),
        }
        if let Some(d) = self.dwell {
            let _ = write!(s, ",\"dwell\":{}", num(d));
        }
        if self.thread {
            s.push_str(",\"thread\":true");
            if self.thread_angle != 0.0 {
                let _ = write!(s, ",\"thread_angle\":{}", num(self.thread_angle));
            }
        }
        if self.exact_stop {
            s.push_str(",\"exact_stop\":true");
        }
        if let Some(t) = self.tolerance {
            let _ = write!(s, ",\"tolerance\":{}", num(t));
        }
        if let Some(c) = &self.css {
            let _ = write!(s, ",\"css\":{{\"m_min\":{}", num(c.m_min));
            if let Some(m) = c.max_rpm {
                let _ = write!(s, ",\"max_rpm\":{}", num(m));
            }
            s.push('}');
        }
        s.push_str(",\"modal\":[");
        for (i, c) in self.modal.codes().iter().enumerate() {
            let _ = write!(s, "{}\"{c}\"", if i > 0 { "," } else { "" });
        }
        s.push_str("]}");
        s
    }

    /// The one-line text form written by `ncplc nc plan --format text`: every field of the JSON
    /// form, `-` for an absent value (`N20 rapid X-20 Y-20 Z50 plane XY F- M3:before S1000 T-`).
    pub fn to_text_line(&self) -> String {
        let mut s = String::with_capacity(96);
        match self.n {
            Some(n) => {
                let _ = write!(s, "N{n}");
            }
            None => s.push_str("N-"),
        }
        if let Some(u) = &self.unit {
            let _ = write!(s, " unit {u}");
        }
        let _ = write!(s, " {}", self.kind.name());
        for (a, v) in &self.end {
            let _ = write!(s, " {a}{}", num(*v));
        }
        if !self.center.is_empty() {
            s.push_str(" center");
            for (a, v) in &self.center {
                let _ = write!(s, " {a}{}", num(*v));
            }
        }
        let (p1, p2) = self.plane.axes();
        let _ = write!(s, " plane {p1}{p2}");
        let opt = |v: Option<String>| v.unwrap_or_else(|| "-".into());
        let _ = write!(s, " F{}", opt(self.feed.map(num)));
        if self.m.is_empty() {
            s.push_str(" M-");
        }
        for m in &self.m {
            let _ = write!(s, " M{}:{}", m.m, if m.before { "before" } else { "after" });
        }
        let _ = write!(s, " S{}", opt(self.s.map(num)));
        let _ = write!(s, " T{}", opt(self.t.map(|t| t.to_string())));
        if let Some(d) = self.dwell {
            let _ = write!(s, " dwell {}", num(d));
        }
        if self.thread {
            s.push_str(" thread");
            if self.thread_angle != 0.0 {
                let _ = write!(s, " I{}", num(self.thread_angle));
            }
        }
        if let Some(c) = &self.css {
            let _ = write!(s, " G96 {}m/min", num(c.m_min));
            if let Some(m) = c.max_rpm {
                let _ = write!(s, " max {}", num(m));
            }
        }
        let _ = write!(s, " modal {}", self.modal.codes().join(","));
        s
    }

    /// The end coordinate of axis `a`.
    pub fn end_of(&self, a: char) -> Option<f64> {
        self.end.iter().find(|(c, _)| *c == a).map(|(_, v)| *v)
    }
}
