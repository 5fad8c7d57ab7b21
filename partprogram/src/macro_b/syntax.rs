//! Reads macro blocks of a Fanuc/HAAS file.
//!
//! A block (a line, or a piece of a line up to `;`) is a macro block when, outside comments, it holds
//! `#` or `[`, starts (after `/` and `N<n>`) with `IF`, `WHILE`, `DO`, `END` or `GOTO`, or holds a
//! `G65` word. Such a block is read here, by recursive descent, into a [`Block`] with a [`Macro`];
//! [`blank`] replaces its bytes with spaces in the copy of the text the ordinary lexer reads, so every
//! span stays that of the original text. Operator priority (Fanuc): functions and `[ ]`, then
//! `* / AND MOD`, then `+ - OR XOR`, then `EQ NE GT GE LT LE` (one per level; combine conditions
//! with brackets: `[#1 GT 0] AND [#2 LT 5]`). Words of an NC macro block may take `#n`, `-#n` or
//! `[expr]` values, except G, M, N, O, P and L (program structure and calls stay literal so that they
//! can be checked before the run; refused with 2010).

use diag::Diagnostic;

use super::{BinOp, Expr, Func, Macro, Stmt, Target, argument_var};
use crate::ast::{Block, Val, Word};
use crate::codes;
use crate::lexer::{Lit, parse_number};

/// A token of a macro block.
#[derive(Debug, Clone, PartialEq)]
enum T<'a> {
    Num(&'a str),
    Hash,
    LBr,
    RBr,
    Eq,
    Plus,
    Minus,
    Star,
    Slash,
    Comma,
    Letter(char),
    Key(&'static str),
}

const KEYS: [&str; 31] = [
    "IF", "THEN", "GOTO", "WHILE", "DO", "END", "EQ", "NE", "GT", "GE", "LT", "LE", "AND", "OR",
    "XOR", "MOD", "SIN", "COS", "TAN", "ASIN", "ACOS", "ATAN", "SQRT", "ABS", "ROUND", "FIX",
    "FUP", "LN", "EXP", "BIN", "BCD",
];

/// Lexes `text` (one block, starting at byte `base` of the file) into tokens with file spans.
/// Tokens with their file spans.
type Toks<'a> = Vec<(T<'a>, (usize, usize))>;

fn lex(text: &str, base: usize) -> Result<Toks<'_>, (usize, usize)> {
    let bytes = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        let c = bytes[i];
        let start = i;
        let tok = match c {
            b' ' | b'\t' | b'\r' => {
                i += 1;
                continue;
            }
            b'(' => {
                while i < bytes.len() && bytes[i] != b')' {
                    i += 1;
                }
                i += 1;
                continue;
            }
            b'#' => T::Hash,
            b'[' => T::LBr,
            b']' => T::RBr,
            b'=' => T::Eq,
            b'+' => T::Plus,
            b'-' => T::Minus,
            b'*' => T::Star,
            b'/' => T::Slash,
            b',' => T::Comma,
            b'0'..=b'9' | b'.' => {
                while i < bytes.len() && (bytes[i].is_ascii_digit() || bytes[i] == b'.') {
                    i += 1;
                }
                out.push((T::Num(&text[start..i]), (base + start, base + i)));
                continue;
            }
            c if c.is_ascii_alphabetic() => {
                while i < bytes.len() && bytes[i].is_ascii_alphabetic() {
                    i += 1;
                }
                let word = text[start..i].to_ascii_uppercase();
                let tok = if word.len() == 1 {
                    T::Letter(char::from(c.to_ascii_uppercase()))
                } else if let Some(k) = KEYS.iter().find(|k| **k == word) {
                    T::Key(k)
                } else {
                    return Err((base + start, base + i));
                };
                out.push((tok, (base + start, base + i)));
                continue;
            }
            _ => {
                let w = text[i..].chars().next().map_or(1, char::len_utf8);
                return Err((base + i, base + i + w));
            }
        };
        i += 1;
        out.push((tok, (base + start, base + i)));
    }
    Ok(out)
}

/// True when block text `text` must be read as a macro block.
pub fn is_macro(text: &str) -> bool {
    let code = strip_comments(text);
    if code.contains('#') || code.contains('[') {
        return true;
    }
    let up = code.to_ascii_uppercase();
    let body = up.trim_start().trim_start_matches('/').trim_start();
    let body = match body.strip_prefix('N') {
        Some(r) => r.trim_start_matches(|c: char| c.is_ascii_digit() || c == ' '),
        None => body,
    };
    if ["IF", "WHILE", "DO", "END", "GOTO"]
        .iter()
        .any(|k| body.starts_with(k))
    {
        return true;
    }
    // A G65 word: G, optional zeros, 65, no further digit.
    let b = up.as_bytes();
    (0..b.len()).any(|i| {
        if b[i] != b'G' {
            return false;
        }
        let mut j = i + 1;
        while j < b.len() && b[j] == b' ' {
            j += 1;
        }
        while j < b.len() && b[j] == b'0' {
            j += 1;
        }
        b[j..].starts_with(b"65")
            && !b
                .get(j + 2)
                .is_some_and(|c| c.is_ascii_digit() || *c == b'.')
    })
}

fn strip_comments(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut depth = false;
    for c in text.chars() {
        match c {
            '(' => depth = true,
            ')' if depth => depth = false,
            c if !depth => out.push(c),
            _ => {}
        }
    }
    out
}

struct P<'a> {
    toks: Vec<(T<'a>, (usize, usize))>,
    at: usize,
    file: &'a str,
    end: usize,
    mac: Macro,
}

type R<X> = Result<X, Diagnostic>;

impl<'a> P<'a> {
    fn peek(&self) -> Option<&T<'a>> {
        self.toks.get(self.at).map(|t| &t.0)
    }

    fn span(&self) -> (usize, usize) {
        self.toks.get(self.at).map_or((self.end, self.end), |t| t.1)
    }

    fn next(&mut self) -> Option<T<'a>> {
        let t = self.toks.get(self.at).map(|t| t.0.clone());
        self.at += 1;
        t
    }

    fn err(&self, msg: impl Into<String>) -> Diagnostic {
        let s = self.span();
        Diagnostic::error(codes::SYNTAX, self.file, s.0..s.1.max(s.0), msg).with_hint(
            "Macro B: #<n> = <expr>; IF [<cond>] GOTO <n>; IF [<cond>] THEN #<n> = <expr>; WHILE [<cond>] DO <1-3> … END <1-3>; GOTO <n>; G65 P<n> L<n> <args>",
        )
    }

    fn expect(&mut self, t: T<'static>, what: &str) -> R<()> {
        if self.peek() == Some(&t) {
            self.at += 1;
            Ok(())
        } else {
            Err(self.err(format!("expected {what}")))
        }
    }

    fn int(&mut self, what: &str) -> R<u32> {
        match self.next() {
            Some(T::Num(s)) if !s.contains('.') && s.len() <= 9 => {
                s.parse().map_err(|_| self.err(format!("expected {what}")))
            }
            _ => {
                self.at -= 1;
                Err(self.err(format!("expected {what}")))
            }
        }
    }

    fn num(&mut self, s: &str) -> R<f64> {
        match s.parse::<f64>() {
            Ok(v) if v.is_finite() && s != "." => Ok(v),
            _ => Err(self.err("invalid number")),
        }
    }

    /// `#n` or `#[expr]` after the `#`.
    fn var(&mut self) -> R<Target> {
        if self.peek() == Some(&T::LBr) {
            self.at += 1;
            let e = self.expr()?;
            self.expect(T::RBr, "`]`")?;
            return Ok(Target::At(e));
        }
        let sp = self.span();
        let n = self.int("a variable number after `#`")?;
        if n != 0 && !super::is_plain(n) && !crate::fanuc_exec::macros::is_system(n) {
            return Err(Diagnostic::error(
                codes::BAD_PARAMETER,
                self.file,
                sp.0..sp.1,
                format!("variable #{n} does not exist"),
            )
            .with_hint(
                "#0 (null), #1–#33 local, #100–#199 and #500–#999 common, system variables see docs/fanuc-conformance.md",
            ));
        }
        Ok(Target::Var(n))
    }

    fn expr(&mut self) -> R<Expr> {
        let a = self.sum()?;
        let op = match self.peek() {
            Some(T::Key("EQ")) => BinOp::Eq,
            Some(T::Key("NE")) => BinOp::Ne,
            Some(T::Key("GT")) => BinOp::Gt,
            Some(T::Key("GE")) => BinOp::Ge,
            Some(T::Key("LT")) => BinOp::Lt,
            Some(T::Key("LE")) => BinOp::Le,
            _ => return Ok(a),
        };
        self.at += 1;
        let b = self.sum()?;
        Ok(Expr::Bin(op, Box::new(a), Box::new(b)))
    }

    fn sum(&mut self) -> R<Expr> {
        let mut a = self.term()?;
        loop {
            let op = match self.peek() {
                Some(T::Plus) => BinOp::Add,
                Some(T::Minus) => BinOp::Sub,
                Some(T::Key("OR")) => BinOp::Or,
                Some(T::Key("XOR")) => BinOp::Xor,
                _ => return Ok(a),
            };
            self.at += 1;
            let b = self.term()?;
            a = Expr::Bin(op, Box::new(a), Box::new(b));
        }
    }

    fn term(&mut self) -> R<Expr> {
        let mut a = self.unary()?;
        loop {
            let op = match self.peek() {
                Some(T::Star) => BinOp::Mul,
                Some(T::Slash) => BinOp::Div,
                Some(T::Key("AND")) => BinOp::And,
                Some(T::Key("MOD")) => BinOp::Mod,
                _ => return Ok(a),
            };
            self.at += 1;
            let b = self.unary()?;
            a = Expr::Bin(op, Box::new(a), Box::new(b));
        }
    }

    fn unary(&mut self) -> R<Expr> {
        match self.peek() {
            Some(T::Minus) => {
                self.at += 1;
                Ok(Expr::Neg(Box::new(self.unary()?)))
            }
            Some(T::Plus) => {
                self.at += 1;
                self.unary()
            }
            _ => self.primary(),
        }
    }

    fn bracket(&mut self) -> R<Expr> {
        self.expect(T::LBr, "`[`")?;
        let e = self.expr()?;
        self.expect(T::RBr, "`]`")?;
        Ok(e)
    }

    fn primary(&mut self) -> R<Expr> {
        let t = self.peek().cloned();
        match t {
            Some(T::Num(s)) => {
                self.at += 1;
                Ok(Expr::Num(self.num(s)?))
            }
            Some(T::Hash) => {
                self.at += 1;
                Ok(match self.var()? {
                    Target::Var(n) => Expr::Var(n),
                    Target::At(e) => Expr::VarAt(Box::new(e)),
                })
            }
            Some(T::LBr) => self.bracket(),
            Some(T::Key("ATAN")) => {
                self.at += 1;
                self.expect(T::LBr, "`[`")?;
                let a = self.expr()?;
                if self.peek() == Some(&T::Comma) {
                    self.at += 1;
                    let b = self.expr()?;
                    self.expect(T::RBr, "`]`")?;
                    return Ok(Expr::Atan2(Box::new(a), Box::new(b)));
                }
                self.expect(T::RBr, "`]`")?;
                if self.peek() == Some(&T::Slash)
                    && self.toks.get(self.at + 1).map(|t| &t.0) == Some(&T::LBr)
                {
                    self.at += 1;
                    let b = self.bracket()?;
                    return Ok(Expr::Atan2(Box::new(a), Box::new(b)));
                }
                Ok(Expr::Call(Func::Atan, Box::new(a)))
            }
            Some(T::Key(k)) => {
                let f = match k {
                    "SIN" => Func::Sin,
                    "COS" => Func::Cos,
                    "TAN" => Func::Tan,
                    "ASIN" => Func::Asin,
                    "ACOS" => Func::Acos,
                    "SQRT" => Func::Sqrt,
                    "ABS" => Func::Abs,
                    "ROUND" => Func::Round,
                    "FIX" => Func::Fix,
                    "FUP" => Func::Fup,
                    "LN" => Func::Ln,
                    "EXP" => Func::Exp,
                    "BIN" => Func::Bin,
                    "BCD" => Func::Bcd,
                    _ => return Err(self.err(format!("`{k}` cannot start a value"))),
                };
                self.at += 1;
                Ok(Expr::Call(f, Box::new(self.bracket()?)))
            }
            _ => Err(self.err("expected a value: a number, #<n>, [<expr>] or a function")),
        }
    }

    fn cond(&mut self) -> R<Expr> {
        self.bracket()
    }

    fn loop_id(&mut self) -> R<u8> {
        let sp = self.span();
        let m = self.int("a loop number 1–3")?;
        if !(1..=3).contains(&m) {
            return Err(Diagnostic::error(
                codes::OUT_OF_RANGE,
                self.file,
                sp.0..sp.1,
                format!("loop number {m}: DO/END take 1, 2 or 3"),
            ));
        }
        Ok(m as u8)
    }

    fn done(&self) -> R<()> {
        if self.at < self.toks.len() {
            Err(self.err("unexpected text after the macro statement"))
        } else {
            Ok(())
        }
    }

    /// A statement or NC words (the `/` and `N` are read by the caller).
    fn body(&mut self, b: &mut Block) -> R<()> {
        let t = self.peek().cloned();
        let stmt = match t {
            Some(T::Hash) => {
                self.at += 1;
                let v = self.var()?;
                self.expect(T::Eq, "`=`")?;
                Stmt::Assign(v, self.expr()?)
            }
            Some(T::Key("IF")) => {
                self.at += 1;
                let c = self.cond()?;
                match self.next() {
                    Some(T::Key("GOTO")) => Stmt::IfGoto(c, self.expr()?),
                    Some(T::Key("THEN")) => {
                        self.expect(T::Hash, "`#` after THEN")?;
                        let v = self.var()?;
                        self.expect(T::Eq, "`=`")?;
                        Stmt::IfThen(c, v, self.expr()?)
                    }
                    _ => {
                        self.at -= 1;
                        return Err(self.err("expected GOTO or THEN after IF [ … ]"));
                    }
                }
            }
            Some(T::Key("WHILE")) => {
                self.at += 1;
                let c = self.cond()?;
                self.expect(T::Key("DO"), "DO")?;
                Stmt::While(Some(c), self.loop_id()?)
            }
            Some(T::Key("DO")) => {
                self.at += 1;
                Stmt::While(None, self.loop_id()?)
            }
            Some(T::Key("END")) => {
                self.at += 1;
                Stmt::End(self.loop_id()?)
            }
            Some(T::Key("GOTO")) => {
                self.at += 1;
                Stmt::Goto(self.expr()?)
            }
            _ => return self.words(b),
        };
        self.done()?;
        self.mac.stmt = Some(stmt);
        Ok(())
    }

    /// NC words whose values may be expressions; a G65 word makes the block a call.
    fn words(&mut self, b: &mut Block) -> R<()> {
        let mut g65 = false;
        while self.at < self.toks.len() {
            let sp0 = self.span();
            let Some(T::Letter(a)) = self.next() else {
                self.at -= 1;
                return Err(self.err("expected an address letter"));
            };
            let vstart = self.at;
            // A literal value (with sign) stays a literal word.
            let sign = match self.peek() {
                Some(T::Minus) => Some("-"),
                Some(T::Plus) => Some("+"),
                _ => None,
            };
            let lit_at = self.at + usize::from(sign.is_some());
            let val = match self.toks.get(lit_at).map(|t| &t.0) {
                Some(T::Num(s)) => {
                    let txt = format!("{}{s}", sign.unwrap_or(""));
                    let l: Lit = parse_number(&txt).ok_or_else(|| self.err("invalid number"))?;
                    self.at = lit_at + 1;
                    Val::Lit(l)
                }
                _ => {
                    let e = self.unary()?;
                    if matches!(a, 'G' | 'M' | 'N' | 'O' | 'P' | 'L') {
                        let s = self.toks[vstart].1;
                        return Err(Diagnostic::error(
                            codes::NOT_PARAMETRISABLE,
                            self.file,
                            sp0.0..s.1,
                            format!("address {a} cannot take a macro expression"),
                        )
                        .with_hint("G, M, N, O, P and L are written literally (they are checked before the run)"));
                    }
                    self.mac.exprs.push(e);
                    Val::Expr((self.mac.exprs.len() - 1) as u32)
                }
            };
            let end = self.toks.get(self.at - 1).map_or(sp0.1, |t| t.1.1);
            if a == 'N' {
                return Err(self.err("the block number comes first"));
            }
            if a == 'G' && matches!(val, Val::Lit(l) if l.milli() == 65_000) {
                g65 = true;
            }
            b.words.push(Word {
                addr: a,
                val,
                span: (sp0.0, end),
            });
        }
        if g65 {
            self.call(b)?;
        }
        Ok(())
    }

    /// Turns the words of a G65 block into [`Stmt::Call`].
    fn call(&mut self, b: &mut Block) -> R<()> {
        let mut p = None;
        let mut l = 1;
        let mut args: Vec<(u8, Expr)> = Vec::new();
        // Argument specification II: I, J, K in this order form a set (up to ten: #4–#33); an
        // address not after the previous one of the set starts the next set.
        let (mut set, mut last) = (0u8, None::<u8>);
        let mut letters: Vec<char> = Vec::new();
        for w in std::mem::take(&mut b.words) {
            let bad = |msg: String| {
                Diagnostic::error(
                    codes::NOT_PARAMETRISABLE,
                    self.file,
                    w.span.0..w.span.1,
                    msg,
                )
                .with_hint("G65 P<program> L<count> and arguments A–Z (specification I) or A B C with up to ten I J K sets (II)")
            };
            let value = match w.val {
                Val::Lit(x) => Expr::Num(x.value()),
                Val::Expr(i) => self.mac.exprs[i as usize].clone(),
                Val::Param(_) => return Err(bad("R parameters are MEFI syntax".into())),
            };
            match w.addr {
                'G' if matches!(w.val, Val::Lit(x) if x.milli() == 65_000) => {}
                'P' => match w.val {
                    Val::Lit(x) if !x.point && (0..=99_999).contains(&x.int) => {
                        p = Some(x.int as u32);
                    }
                    _ => return Err(bad("G65 P: a program number 0..99999".into())),
                },
                'L' => match w.val {
                    Val::Lit(x) if !x.point && (0..=9999).contains(&x.int) => l = x.int as u32,
                    _ => return Err(bad("G65 L: a repeat count 0..9999".into())),
                },
                a @ ('I' | 'J' | 'K') => {
                    let pos = a as u8 - b'I';
                    if last.is_none_or(|l| pos <= l) {
                        set += 1;
                    }
                    last = Some(pos);
                    if set > 10 {
                        return Err(bad(format!(
                            "{a}: more than ten I, J, K sets (argument specification II)"
                        )));
                    }
                    put_arg(&mut args, 4 + 3 * (set - 1) + pos, value);
                }
                a => match argument_var(a) {
                    Some(_) if letters.contains(&a) => {
                        return Err(bad(format!("argument {a} given twice")));
                    }
                    Some(v) => {
                        letters.push(a);
                        put_arg(&mut args, v, value);
                    }
                    None => {
                        return Err(bad(format!(
                            "address {a} is not a G65 argument (G, L, N, O, P are not)"
                        )));
                    }
                },
            }
        }
        let Some(p) = p else {
            return Err(Diagnostic::error(
                codes::MISSING_L,
                self.file,
                b.span.0..b.span.1,
                "G65 needs P<program number>",
            ));
        };
        self.mac.exprs.clear();
        self.mac.stmt = Some(Stmt::Call { p, l, args });
        Ok(())
    }
}

/// Binds local `v` to `value`; a variable given twice (specification I and II mixed, e.g. `D` and the
/// second `I`) takes the later value, as Fanuc does.
fn put_arg(args: &mut Vec<(u8, Expr)>, v: u8, value: Expr) {
    match args.iter_mut().find(|(u, _)| *u == v) {
        Some(slot) => slot.1 = value,
        None => args.push((v, value)),
    }
}

/// Reads macro block `text` at byte `base` of `file` into a block.
pub fn parse_block(file: &str, text: &str, base: usize) -> Result<Block, Diagnostic> {
    let toks = lex(text, base).map_err(|s| {
        Diagnostic::error(
            codes::BAD_CHAR,
            file,
            s.0..s.1,
            format!(
                "`{}` is not allowed here",
                text.get(s.0 - base..s.1 - base).unwrap_or("?")
            ),
        )
        .with_hint("Macro B words: # [ ] + - * / = and IF THEN GOTO WHILE DO END EQ NE GT GE LT LE AND OR XOR MOD and the functions")
    })?;
    let end = base + text.trim_end().len();
    let mut p = P {
        toks,
        at: 0,
        file,
        end,
        mac: Macro::default(),
    };
    let mut b = Block {
        span: (p.span().0, end),
        ..Block::default()
    };
    if p.peek() == Some(&T::Slash) {
        p.at += 1;
        b.skip = true;
    }
    if p.peek() == Some(&T::Letter('N')) {
        p.at += 1;
        let n = p.int("a block number after N")?;
        b.n = Some(n);
    }
    p.body(&mut b)?;
    b.mac = Some(Box::new(p.mac));
    Ok(b)
}

/// Finds the macro blocks of Fanuc text `src`: their byte ranges in file order, which the lexer
/// steps over ([`crate::lexer::Lexer::skipping`]) and the grouping reads ([`parse_block`]) when it
/// reaches them (issue 23: 16 bytes per macro block are held until then, not the block, and the
/// text is not copied). One pass over the pieces of the text (lines and `;`-separated blocks, a
/// comment's `;` not counted) as they end: each range starts after a line end or `;` and ends at
/// one or at the end of the text.
pub fn prepass(src: &str) -> Vec<(usize, usize)> {
    let bytes = src.as_bytes();
    let mut pieces = Vec::new();
    let mut piece = |s: usize, e: usize| {
        let Some(piece) = src.get(s..e) else {
            return;
        };
        if !piece.contains(['#', '[', 'G', 'g', 'I', 'i', 'W', 'w', 'D', 'd', 'E', 'e'])
            || !is_macro(piece)
        {
            return;
        }
        pieces.push((s, e));
    };
    let (mut start, mut comment) = (0, false);
    for (i, &c) in bytes.iter().enumerate() {
        match c {
            b'(' => comment = true,
            b')' => comment = false,
            b'\n' | b'\r' => {
                comment = false;
                piece(start, i);
                start = i + 1;
            }
            b';' if !comment => {
                piece(start, i);
                start = i + 1;
            }
            _ => {}
        }
    }
    piece(start, bytes.len());
    pieces
}
