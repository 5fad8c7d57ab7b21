//! Semantic tokens: the lexer's tokens (and the `;` comments it skips) classified for
//! highlighting, encoded as LSP's relative five-number groups (UTF-16 columns).

use compiler::lexer::{Tok, tokenize};
use lsp_types::{SemanticToken, SemanticTokenType, SemanticTokensLegend};

use crate::keywords;
use crate::text::Text;

/// The token types, in legend order.
pub const TYPES: &[SemanticTokenType] = &[
    SemanticTokenType::KEYWORD,
    SemanticTokenType::VARIABLE,
    SemanticTokenType::FUNCTION,
    SemanticTokenType::NUMBER,
    SemanticTokenType::OPERATOR,
    SemanticTokenType::COMMENT,
    SemanticTokenType::TYPE,
    SemanticTokenType::PROPERTY,
    SemanticTokenType::MACRO,
];

/// The legend the server announces.
pub fn legend() -> SemanticTokensLegend {
    SemanticTokensLegend {
        token_types: TYPES.to_vec(),
        token_modifiers: Vec::new(),
    }
}

const KEYWORD: u32 = 0;
const VARIABLE: u32 = 1;
const FUNCTION: u32 = 2;
const NUMBER: u32 = 3;
const OPERATOR: u32 = 4;
const COMMENT: u32 = 5;
const TYPE: u32 = 6;
const SIGNAL: u32 = 7;
const PULSE: u32 = 8;

/// `(start, end, type)` of every highlighted token of `src`, in order.
pub fn classify(src: &str) -> Vec<(usize, usize, u32)> {
    let (toks, _) = tokenize(src);
    let mut out = Vec::with_capacity(toks.len());
    for (i, (s, t, e)) in toks.iter().enumerate() {
        let prev = i.checked_sub(1).and_then(|j| toks.get(j)).map(|t| &t.1);
        let next = toks.get(i + 1).map(|t| &t.1);
        let class = match t {
            Tok::Signal(_) => SIGNAL,
            Tok::Pulse(_) => PULSE,
            Tok::Int(_) | Tok::Real(_) | Tok::Duration(_) => NUMBER,
            Tok::Ident(w) => {
                let up = w.to_ascii_uppercase();
                if prev == Some(&Tok::Colon) && keywords::TYPES.contains(&up.as_str()) {
                    TYPE
                } else if next == Some(&Tok::LParen) && keywords::FUNCTIONS.contains(&up.as_str()) {
                    FUNCTION
                } else {
                    VARIABLE
                }
            }
            Tok::Def
            | Tok::At
            | Tok::Retain
            | Tok::Set
            | Tok::Res
            | Tok::If
            | Tok::Then
            | Tok::Else
            | Tok::EndIf
            | Tok::OrKw
            | Tok::AndKw
            | Tok::NotKw
            | Tok::XorKw
            | Tok::Mod
            | Tok::True
            | Tok::False
            | Tok::Dollar => KEYWORD,
            Tok::Eq
            | Tok::Ne
            | Tok::Lt
            | Tok::Le
            | Tok::Gt
            | Tok::Ge
            | Tok::Plus
            | Tok::Minus
            | Tok::Star
            | Tok::Slash
            | Tok::Amp
            | Tok::Pipe
            | Tok::Caret
            | Tok::Tilde
            | Tok::Shl
            | Tok::Shr
            | Tok::Assign => OPERATOR,
            _ => continue,
        };
        if e > s {
            out.push((*s, *e, class));
        }
    }
    // Comments: `;` to the end of the line (the language has no strings, so any `;` starts one).
    let mut at = 0;
    for line in src.split_inclusive('\n') {
        if let Some(i) = line.find(';') {
            let end = line.trim_end_matches(['\n', '\r']).len();
            out.push((at + i, at + end, COMMENT));
        }
        at += line.len();
    }
    out.sort_unstable_by_key(|t| t.0);
    out
}

/// The encoded tokens of `text`.
pub fn semantic_tokens(text: &Text) -> Vec<SemanticToken> {
    let src = text.as_str();
    let mut out = Vec::new();
    let (mut line, mut col) = (0u32, 0u32);
    for (s, e, class) in classify(src) {
        let p = text.position(s);
        let len: usize = src
            .get(s..e)
            .unwrap_or("")
            .chars()
            .map(char::len_utf16)
            .sum();
        let delta_start = if p.line == line {
            p.character - col
        } else {
            p.character
        };
        out.push(SemanticToken {
            delta_line: p.line - line,
            delta_start,
            length: len as u32,
            token_type: class,
            token_modifiers_bitset: 0,
        });
        (line, col) = (p.line, p.character);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_line_is_classified_token_by_token() {
        let src = "DEF t : TON(2s) ; delay\nU4A0 = t * /P1\n";
        let got: Vec<(&str, u32)> = classify(src)
            .iter()
            .map(|&(s, e, c)| (&src[s..e], c))
            .collect();
        assert_eq!(
            got,
            vec![
                ("DEF", KEYWORD),
                ("t", VARIABLE),
                ("TON", TYPE),
                ("2s", NUMBER),
                ("; delay", COMMENT),
                ("U4A0", SIGNAL),
                ("=", OPERATOR),
                ("t", VARIABLE),
                ("*", OPERATOR),
                ("/", OPERATOR),
                ("P1", PULSE),
            ]
        );
        let enc = semantic_tokens(&Text::new(src.to_string()));
        assert_eq!(
            (enc[5].delta_line, enc[5].delta_start, enc[5].length),
            (1, 0, 4)
        );
        assert_eq!(
            (enc[1].delta_line, enc[1].delta_start, enc[1].length),
            (0, 4, 1)
        );
    }
}
