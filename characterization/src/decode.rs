//! Decoding characterization bytes into text, one character per byte for legacy code pages.
//!
//! Valid UTF-8 is kept as it is. Anything else is CP866 or CP1251 (DOS and Windows Cyrillic): the
//! code page whose Cyrillic letter range holds more of the bytes wins, and every byte ≥ 0x80
//! becomes exactly one character, so a file keeps its lines and its columns. Bytes that are not
//! Cyrillic letters in the chosen page map to the Latin-1 character of the same number.

/// Decodes file bytes: valid UTF-8 as is, otherwise CP866 or CP1251 (whichever fits the bytes
/// better), one character per byte, so the text keeps one line per line and one column per byte.
pub fn decode(bytes: &[u8]) -> String {
    if let Ok(s) = std::str::from_utf8(bytes) {
        return s.to_string();
    }
    // CP1251 puts the Cyrillic letters at C0..FF, CP866 at 80..AF and E0..EF.
    let cp1251 = bytes.iter().filter(|&&b| b >= 0xC0).count();
    let cp866 = bytes
        .iter()
        .filter(|&&b| (0x80..=0xAF).contains(&b) || (0xE0..=0xEF).contains(&b))
        .count();
    let use_866 = cp866 > cp1251;
    bytes
        .iter()
        .map(|&b| {
            if b < 0x80 {
                char::from(b)
            } else if use_866 {
                cp866_char(b)
            } else {
                cp1251_char(b)
            }
        })
        .collect()
}

fn cyrillic(offset: u32) -> char {
    char::from_u32(0x0410 + offset).unwrap_or('\u{FFFD}')
}

fn cp866_char(b: u8) -> char {
    match b {
        0x80..=0xAF => cyrillic(u32::from(b - 0x80)),
        0xE0..=0xEF => cyrillic(u32::from(b - 0xE0) + 0x30),
        0xF0 => 'Ё',
        0xF1 => 'ё',
        // Box drawing and the rest: keep one visible character per byte.
        _ => char::from(b),
    }
}

fn cp1251_char(b: u8) -> char {
    match b {
        0xC0..=0xFF => cyrillic(u32::from(b - 0xC0)),
        0xA8 => 'Ё',
        0xB8 => 'ё',
        _ => char::from(b),
    }
}

/// The Latin letter a Cyrillic homoglyph stands for (`В` → `B`), as found in OCR'd manuals.
pub fn homoglyph(c: char) -> Option<char> {
    Some(match c {
        'А' => 'A',
        'В' => 'B',
        'С' => 'C',
        'Е' => 'E',
        'Н' => 'H',
        'К' => 'K',
        'М' => 'M',
        'О' => 'O',
        'Р' => 'P',
        'Т' => 'T',
        'Х' => 'X',
        'У' => 'Y',
        'а' => 'a',
        'е' => 'e',
        'о' => 'o',
        'р' => 'p',
        'с' => 'c',
        'х' => 'x',
        _ => return None,
    })
}
