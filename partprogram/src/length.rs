//! Tool length correction: which length each axis takes from a correction entry, for the MEFI
//! methods A, B and C (machine constant 329 decade 7, structure-motion spec §13.8) and for the Fanuc
//! G43/G44 tool axis (HAAS spec §10.1).
//!
//! A correction entry is `[radius, length axis 1, …, length axis 4]`. Method A: each digit of
//! `&k1k2k3k4` (k1 = axis 1) is 0 (none), 1 (add) or 2 (subtract). Method B: `D<n>` alone activates
//! every length of entry n, added (the sign is not stated: inferred add), `D0` cancels, `&` has no
//! effect. Method C: `&1` activates every length of entry D (the axes are not stated: inferred as B),
//! `&0` cancels, other `&` values are errors. Fanuc: the tool axis is the axis normal to the plane
//! selected when G43/G44 is programmed (G17 → Z, G18 → Y, G19 → X); its length is the datum of that
//! axis's ordinal (a mill's Z is axis 3: datum IV, `Z=` in `TAB0.KOR`).

use crate::canon::Plane;
use crate::machine::LengthMethod;

/// The lengths of axes 1..4 that MEFI correction `&amp` with entry `entry` applies under `method`;
/// an error message when `amp` is not valid for the method.
pub fn mefi_lengths(method: LengthMethod, amp: i64, entry: &[f64; 5]) -> Result<[f64; 4], String> {
    let all = [entry[1], entry[2], entry[3], entry[4]];
    match method {
        LengthMethod::A => {
            let valid = (0..=2222).contains(&amp) && (0..4).all(|k| (amp / 10i64.pow(k)) % 10 <= 2);
            if !valid {
                return Err(format!(
                    "&{amp}: each of the 4 digits of & must be 0, 1 or 2 (length correction method A)"
                ));
            }
            let mut out = [0.0; 4];
            for (k, o) in out.iter_mut().enumerate() {
                let digit = (amp / 10i64.pow(3 - k as u32)) % 10;
                *o = match digit {
                    1 => all[k],
                    2 => -all[k],
                    _ => 0.0,
                };
            }
            Ok(out)
        }
        LengthMethod::B => Ok(all),
        LengthMethod::C => match amp {
            0 => Ok([0.0; 4]),
            1 => Ok(all),
            _ => Err(format!(
                "&{amp}: under length correction method C & is 0 (cancel) or 1 (activate entry D)"
            )),
        },
    }
}

/// The Fanuc tool axis of G43/G44 in `plane`: the axis normal to it (none for a MEFI G14–G16 plane).
pub fn tool_axis(plane: Plane) -> Option<char> {
    match plane {
        Plane::XY => Some('Z'),
        Plane::ZX => Some('Y'),
        Plane::YZ => Some('X'),
        Plane::Extra { .. } => None,
    }
}

/// The length datum (index into a correction entry) of the machine axis with index `axis`: axes 1..4
/// have data II..V; `None` for axes 5 and 6, which have no length in the table.
pub fn datum_of_axis(axis: usize) -> Option<usize> {
    (axis < 4).then_some(axis + 1)
}
