//! Generator of random Fanuc/HAAS programs inside the overlap with LinuxCNC's rs274: lines, arcs, full
//! circles and helices in the three planes, G90/G91, G54–G59 written by G10 L2, G52, G92, G28, the
//! canned cycles G73/G81/G82/G83/G85/G89 with G98/G99 and L, G41/G42 with D, G43/G49 with H, M98 with
//! L calling a subprogram stored after M30 in the same file.
//!
//! Kept out by construction (known, intended differences, README): G04/G82 P without a decimal point
//! (HAAS milliseconds, LinuxCNC seconds: P is always written with a point), peck retract amounts of
//! G73/G83 (compared without the peck moves), G52 after G92 (LinuxCNC's G52 replaces the G92 offset),
//! G43 followed by an incremental Z (Fanuc moves by the length), G28 under G43 (HAAS cancels the
//! length, LinuxCNC keeps it), G10 L20 (LinuxCNC: "current position becomes", HAAS: G154 offsets),
//! G84/G74/G86 (spindle-synchronised or dwell-less in LinuxCNC), cycles with the R plane above the
//! initial level, canned cycles in G91 continued by a second block (LinuxCNC re-bases R on the
//! current Z), G85/G89 under G98 (Fanuc feeds out to R, LinuxCNC to the initial level), the
//! start-up of G41/G42 at an angle (Fanuc type A ends the entry at the next element's offset point,
//! LinuxCNC perpendicular to the entry move: entries and exits are collinear here).
//!
//! Macros inside the overlap ([`MExpr`]): numbered parameters #100–#103 and #500–#501 (set in the
//! header, so Fanuc's null never meets LinuxCNC's 0), one `#i=[…]` assignment per block, and words
//! written as expressions with `+ - * /`, `GT`/`LT`, unary minus, `ABS SQRT ROUND FIX FUP SIN COS`,
//! `ATAN[a]/[b]` and `MOD`. Kept out by construction (intended differences): `FIX`/`FUP` of a
//! negative value (LinuxCNC floor/ceil, Fanuc towards/away from zero: the argument is taken ABS),
//! `MOD` of negative or fractional operands (Fanuc rounds the operands, LinuxCNC keeps them and
//! returns a non-negative remainder: written `[ROUND[ABS[a]] MOD k]`), `ATAN` of a negative
//! numerator (Fanuc 0..360, LinuxCNC −180..180) or of a denominator that may be zero in exact
//! arithmetic (LinuxCNC computes SIN/COS in long double: `COS[90]` is −2.5e-20 there and +6.1e-17
//! in f64, and `ATAN[0]/[COS[90]]` is 180 there, 0 here): written `ATAN[ABS[a]]/[ABS[b] + 1]`,
//! division by a value that can be zero (divisors are constants), and several assignments in one
//! block (LinuxCNC sets them after the block). Word values differ by Fanuc's rounding to 0.001 mm
//! (the least input increment; LinuxCNC does not round): expression words are used in G90 only, and
//! a G92 after an expression move is preceded by a literal move, so a rounded position never
//! becomes part of an offset where a second rounded word would add to it (seed 14 found both).

use proptest::prelude::*;

/// Pythagorean triples (a, b, r): arc points with exact coordinates.
const TRIPLES: [(i32, i32, i32); 4] = [(3, 4, 5), (5, 12, 13), (8, 6, 10), (0, 5, 5)];

/// One random statement (its parameters; rendering adapts it to the state).
#[derive(Debug, Clone)]
pub enum Stmt {
    /// G00/G01 to an absolute point, or by an increment.
    Line { rapid: bool, abs: bool, p: [i32; 3] },
    /// Arc in plane 0/1/2 with centre words, sweep between two points of a triple circle.
    Arc {
        plane: u8,
        cw: bool,
        tri: u8,
        from: u8,
        to: u8,
        k: i32,
        helix: i32,
        full: bool,
    },
    /// G10 L2 P<p> then select it.
    Offset { p: u8, v: [i32; 3] },
    /// G52 (all three axes) or its cancellation.
    Local { v: [i32; 3], cancel: bool },
    /// G92 with all three axes.
    Set { v: [i32; 3] },
    /// G28 without axes, or G91 G28 Z0.
    Home { all: bool },
    /// A canned cycle.
    Cycle {
        g: u8,
        g99: bool,
        inc: bool,
        xy: [i32; 2],
        depth: i32,
        r: i32,
        q: i32,
        l: u8,
        second: Option<[i32; 2]>,
    },
    /// G43 H<h> Z (h 1 or 2) or G49 Z.
    Length { h: u8, z: i32 },
    /// G41/G42 D on a rectangle in G91.
    Comp { left: bool, d: u8, w: i32, h: i32 },
    /// M98 P2000 L<l>.
    Call { l: u8 },
    /// `#<var>=[e]`.
    Param { var: u8, e: MExpr },
    /// `G90 G00/G01` with every coordinate an expression.
    ExprMove { rapid: bool, e: [MExpr; 3] },
}

/// Parameters the macro statements use (set in the header).
const PARAMS: [&str; 6] = ["#100", "#101", "#102", "#103", "#500", "#501"];

/// A macro expression inside the overlap of Fanuc Macro B and LinuxCNC (module doc).
#[derive(Debug, Clone)]
pub enum MExpr {
    /// A number (half millimetres).
    Num(i32),
    /// A parameter of [`PARAMS`].
    Var(u8),
    /// `[a + b]`, `[a - b]`, `[a GT b]`, `[a LT b]` (op 0..4).
    Bin(u8, Box<MExpr>, Box<MExpr>),
    /// `[a * k]` for k 0.25, 0.5, 1.5, 2; `[a / k]` for k 2, 4, 5, 8 (op 0..8).
    Scale(u8, Box<MExpr>),
    /// `ABS SQRT ROUND FIX FUP SIN COS` (f 0..7), `ATAN[ABS[a]]/[b]` (7), `[ROUND[ABS[a]] MOD k]`
    /// (8, k from b's size), `-a` (9).
    Func(u8, Box<MExpr>, Box<MExpr>),
}

impl MExpr {
    /// The text both dialects read.
    pub fn text(&self) -> String {
        match self {
            MExpr::Num(v) => mm(*v),
            MExpr::Var(i) => PARAMS[usize::from(*i) % PARAMS.len()].to_string(),
            MExpr::Bin(op, a, b) => {
                let o = ["+", "-", "GT", "LT"][usize::from(*op) % 4];
                format!("[{} {o} {}]", a.text(), b.text())
            }
            MExpr::Scale(k, a) => {
                let (o, k) = [
                    ("*", "0.25"),
                    ("*", "0.5"),
                    ("*", "1.5"),
                    ("*", "2"),
                    ("/", "2"),
                    ("/", "4"),
                    ("/", "5"),
                    ("/", "8"),
                ][usize::from(*k) % 8];
                format!("[{} {o} {k}]", a.text())
            }
            MExpr::Func(f, a, b) => {
                let (a, b) = (a.text(), b.text());
                match f % 10 {
                    0 => format!("ABS[{a}]"),
                    1 => format!("SQRT[ABS[{a}]]"),
                    2 => format!("ROUND[{a}]"),
                    3 => format!("FIX[ABS[{a}]]"),
                    4 => format!("FUP[ABS[{a}]]"),
                    5 => format!("[SIN[{a}] * 10]"),
                    6 => format!("[COS[{a}] * 10]"),
                    7 => format!("[ATAN[ABS[{a}]]/[ABS[{b}] + 1] / 10]"),
                    8 => format!("[ROUND[ABS[{a}]] MOD {}]", 2 + b.len() % 5),
                    _ => format!("-[{a}]"),
                }
            }
        }
    }
}

/// Strategy of a macro expression (depth ≤ 3).
pub fn mexpr() -> impl Strategy<Value = MExpr> {
    let leaf = prop_oneof![
        (-40..40i32).prop_map(MExpr::Num),
        (0..6u8).prop_map(MExpr::Var),
    ];
    leaf.prop_recursive(3, 12, 2, |inner| {
        prop_oneof![
            (0..4u8, inner.clone(), inner.clone()).prop_map(|(o, a, b)| MExpr::Bin(
                o,
                Box::new(a),
                Box::new(b)
            )),
            (0..8u8, inner.clone()).prop_map(|(k, a)| MExpr::Scale(k, Box::new(a))),
            (0..10u8, inner.clone(), inner).prop_map(|(f, a, b)| MExpr::Func(
                f,
                Box::new(a),
                Box::new(b)
            )),
        ]
    })
}

fn pt() -> impl Strategy<Value = [i32; 3]> {
    [-80..80i32, -80..80i32, -40..40i32]
}

/// Strategy of one statement.
pub fn stmt() -> impl Strategy<Value = Stmt> {
    prop_oneof![
        3 => (any::<bool>(), any::<bool>(), pt()).prop_map(|(rapid, abs, p)| Stmt::Line { rapid, abs, p }),
        4 => (0..3u8, any::<bool>(), 0..4u8, 0..8u8, 0..8u8, 1..4i32, -10..10i32, any::<bool>())
            .prop_map(|(plane, cw, tri, from, to, k, helix, full)| Stmt::Arc { plane, cw, tri, from, to, k, helix, full }),
        1 => (1..7u8, pt()).prop_map(|(p, v)| Stmt::Offset { p, v }),
        1 => (pt(), any::<bool>()).prop_map(|(v, cancel)| Stmt::Local { v, cancel }),
        1 => pt().prop_map(|v| Stmt::Set { v }),
        1 => any::<bool>().prop_map(|all| Stmt::Home { all }),
        3 => (0..6u8, any::<bool>(), any::<bool>(), [-60..60i32, -60..60i32], 1..30i32, 0..10i32, 1..8i32, 1..4u8,
              proptest::option::of([-60..60i32, -60..60i32]))
            .prop_map(|(g, g99, inc, xy, depth, r, q, l, second)| Stmt::Cycle { g, g99, inc, xy, depth, r, q, l, second }),
        1 => (0..3u8, 20..60i32).prop_map(|(h, z)| Stmt::Length { h, z }),
        2 => (any::<bool>(), 1..3u8, 20..60i32, 20..60i32).prop_map(|(left, d, w, h)| Stmt::Comp { left, d, w, h }),
        1 => (1..4u8).prop_map(|l| Stmt::Call { l }),
        2 => (0..6u8, mexpr()).prop_map(|(var, e)| Stmt::Param { var, e }),
        2 => (any::<bool>(), [mexpr(), mexpr(), mexpr()]).prop_map(|(rapid, e)| Stmt::ExprMove { rapid, e }),
    ]
}

/// Strategy of a whole program: statements and the subprogram's increments.
pub fn program() -> impl Strategy<Value = (Vec<Stmt>, [i32; 2])> {
    (
        proptest::collection::vec(stmt(), 3..14),
        [-20..20i32, -20..20i32],
    )
}

fn mm(v: i32) -> String {
    format!("{:.3}", f64::from(v) * 0.5)
}

/// A rendered program: the text and the N numbers of its peck-cycle blocks.
pub struct Rendered {
    /// Program text (Fanuc and rs274 read the same text).
    pub text: String,
    /// Blocks whose peck moves are left out of the comparison.
    pub pecks: Vec<u32>,
}

struct W {
    out: String,
    n: u32,
    pecks: Vec<u32>,
}

impl W {
    fn b(&mut self, s: &str) -> u32 {
        self.n += 1;
        self.out.push_str(&format!("N{} {s}\n", self.n));
        self.n
    }
}

/// Renders a program: header, the statements, M30, then the subprogram O2000.
pub fn render(stmts: &[Stmt], sub: [i32; 2]) -> Rendered {
    let mut w = W {
        out: "O1000\n".into(),
        n: 0,
        pecks: Vec::new(),
    };
    w.b("G21 G17 G90 G94 G40 G49 G80 G54 G98");
    w.b("F200.");
    w.b("G00 X0 Y0 Z20.");
    for (p, v) in PARAMS
        .iter()
        .zip(["12.5", "-3.25", "7.", "0.5", "-20.", "45."])
    {
        w.b(&format!("{p}={v}"));
    }
    let (mut g92, mut tlo) = (false, false);
    // The position was reached through an expression word (rounded by Fanuc, not by LinuxCNC).
    let mut rounded = false;
    for s in stmts {
        match s {
            Stmt::Line { rapid, abs, p } => {
                let g = if *rapid { "G00" } else { "G01" };
                if *abs {
                    rounded = false;
                    w.b(&format!(
                        "G90 {g} X{} Y{} Z{}",
                        mm(p[0]),
                        mm(p[1]),
                        mm(p[2])
                    ));
                } else {
                    w.b(&format!(
                        "G91 {g} X{} Y{} Z{}",
                        mm(p[0]),
                        mm(p[1]),
                        mm(p[2] / 2)
                    ));
                    w.b("G90");
                }
            }
            Stmt::Arc {
                plane,
                cw,
                tri,
                from,
                to,
                k,
                helix,
                full,
            } => {
                let (a, b, _) = TRIPLES[usize::from(*tri) % TRIPLES.len()];
                let pts = [
                    (a, b),
                    (b, a),
                    (-a, b),
                    (-b, a),
                    (-a, -b),
                    (-b, -a),
                    (a, -b),
                    (b, -a),
                ];
                let s = pts[usize::from(*from)];
                let e = pts[usize::from(*to)];
                let (g, axes, cw_) = (["G17", "G18", "G19"][usize::from(*plane)], *plane, *cw);
                let (a1, a2, c1, c2, third) = match axes {
                    0 => ("X", "Y", "I", "J", "Z"),
                    1 => ("Z", "X", "K", "I", "Y"),
                    _ => ("Y", "Z", "J", "K", "X"),
                };
                let gm = if cw_ { "G02" } else { "G03" };
                // Centre = start - s; end = centre + e: increment e - s.
                let (ci, cj) = (-s.0 * k * 2, -s.1 * k * 2);
                let (di, dj) = ((e.0 - s.0) * k * 2, (e.1 - s.1) * k * 2);
                if *full {
                    w.b(&format!("{g} G91 {gm} {c1}{} {c2}{}", mm(ci), mm(cj)));
                } else {
                    w.b(&format!(
                        "{g} G91 {gm} {a1}{} {a2}{} {third}{} {c1}{} {c2}{}",
                        mm(di),
                        mm(dj),
                        mm(*helix),
                        mm(ci),
                        mm(cj)
                    ));
                }
                w.b("G17 G90");
            }
            Stmt::Offset { p, v } => {
                w.b(&format!(
                    "G10 L2 P{p} X{} Y{} Z{}",
                    mm(v[0]),
                    mm(v[1]),
                    mm(v[2] / 4)
                ));
                w.b(&format!("G{} G00 X0 Y0", 53 + p));
            }
            Stmt::Local { v, cancel } if !g92 => {
                if *cancel {
                    w.b("G52 X0 Y0 Z0");
                } else {
                    w.b(&format!(
                        "G52 X{} Y{} Z{}",
                        mm(v[0] / 2),
                        mm(v[1] / 2),
                        mm(v[2] / 4)
                    ));
                }
            }
            Stmt::Local { .. } => {}
            Stmt::Set { v } => {
                g92 = true;
                if rounded {
                    // G92 would make the rounding difference of the position part of every later
                    // point, where a second rounded word adds to it: start from a literal point.
                    w.b("G90 G00 X0 Y0 Z20.");
                    rounded = false;
                }
                w.b(&format!("G92 X{} Y{} Z{}", mm(v[0]), mm(v[1]), mm(v[2])));
            }
            Stmt::Home { all } => {
                if tlo {
                    w.b("G49 G00 Z20.");
                    tlo = false;
                }
                if *all {
                    w.b("G28");
                } else {
                    w.b("G91 G28 Z0");
                    w.b("G90");
                }
            }
            Stmt::Cycle {
                g,
                g99,
                inc,
                xy,
                depth,
                r,
                q,
                l,
                second,
            } => {
                let code = [73, 81, 82, 83, 85, 89][usize::from(*g)];
                let peck = matches!(code, 73 | 83);
                // G85/G89 feed out to the R plane (Fanuc), LinuxCNC to the clearance level: under
                // G99 the two are the same.
                let ret = if *g99 || matches!(code, 85 | 89) {
                    "G99"
                } else {
                    "G98"
                };
                let extra = match code {
                    73 | 83 => format!(" Q{}", mm(*q)),
                    82 | 89 => " P0.5".into(),
                    _ => String::new(),
                };
                let init = r + 4;
                w.b(&format!("G90 G00 Z{}", mm(init)));
                // One hole per peck block: L repeats are compared on the other cycles.
                let lw = if peck {
                    String::new()
                } else {
                    format!(" L{l}")
                };
                if *inc {
                    let n = w.b(&format!(
                        "G91 {ret} G{code} X{} Y{} Z{} R{}{extra}{lw}",
                        mm(xy[0] / 4),
                        mm(xy[1] / 4),
                        mm(-depth),
                        mm(-4),
                    ));
                    if peck {
                        w.pecks.push(n);
                    }
                    w.b("G80 G90");
                } else {
                    let n = w.b(&format!(
                        "{ret} G{code} X{} Y{} Z{} R{}{extra}{lw}",
                        mm(xy[0]),
                        mm(xy[1]),
                        mm(r - depth),
                        mm(*r),
                    ));
                    if peck {
                        w.pecks.push(n);
                    }
                    if let Some(s) = second {
                        let n = w.b(&format!("X{} Y{}", mm(s[0]), mm(s[1])));
                        if peck {
                            w.pecks.push(n);
                        }
                    }
                    w.b("G80");
                }
            }
            Stmt::Length { h, z } => {
                if *h == 0 {
                    w.b(&format!("G49 G00 Z{}", mm(*z)));
                    tlo = false;
                } else {
                    w.b(&format!("G43 H{h} G00 Z{}", mm(*z)));
                    tlo = true;
                }
            }
            Stmt::Comp { left, d, w: wd, h } => {
                let g = if *left { "G41" } else { "G42" };
                w.b("G91");
                // Entry and exit collinear with the first and last element: Fanuc's start-up
                // type A and LinuxCNC's perpendicular entry then give the same point.
                w.b(&format!("{g} D{d} G01 X{} Y0", mm(40)));
                w.b(&format!("X{}", mm(*wd)));
                w.b(&format!("Y{}", mm(*h)));
                w.b(&format!("X{}", mm(-wd)));
                w.b(&format!("G40 G01 X{} Y0", mm(-40)));
                w.b("G90");
            }
            Stmt::Call { l } => {
                w.b(&format!("M98 P2000 L{l}"));
            }
            Stmt::Param { var, e } => {
                let p = PARAMS[usize::from(*var) % PARAMS.len()];
                w.b(&format!("{p}=[{}]", e.text()));
            }
            Stmt::ExprMove { rapid, e } => {
                let g = if *rapid { "G00" } else { "G01" };
                rounded = true;
                w.b(&format!(
                    "G90 {g} X[{}] Y[{}] Z[{}]",
                    e[0].text(),
                    e[1].text(),
                    e[2].text()
                ));
            }
        }
    }
    w.b("M30");
    w.out.push_str("O2000\n");
    w.b(&format!("G91 G01 X{} Y{}", mm(sub[0]), mm(sub[1])));
    w.b("G90");
    w.b("M99");
    Rendered {
        text: w.out,
        pecks: w.pecks,
    }
}
