//! Transcendental functions of `f64` that give the same bits on every machine.
//!
//! `f64::sin` and its siblings call the platform's C library, whose last bit may differ between
//! library versions and processor architectures. Axis set points, planned arcs and Macro B values
//! are recorded in traces and compared bit for bit on replay, on whatever machine replays them,
//! so every numeric path of ncplc uses these instead: a pure-Rust port of musl's libm (the `libm`
//! crate), the same code everywhere. `sqrt`, `abs`, `mul_add`-free arithmetic and `powi` are
//! already exact or compiler-defined and stay as they are. `clippy.toml` disallows the `std`
//! methods so that new code cannot slip back.

/// The deterministic versions of the `f64` methods, named with a `d` in front (`x.dsin()`), so
/// that a call reads like the method it replaces.
pub trait Det: Sized {
    /// Sine (radians).
    fn dsin(self) -> f64;
    /// Cosine (radians).
    fn dcos(self) -> f64;
    /// Tangent (radians).
    fn dtan(self) -> f64;
    /// Arcsine, radians in [−π/2, π/2].
    fn dasin(self) -> f64;
    /// Arccosine, radians in [0, π].
    fn dacos(self) -> f64;
    /// Arctangent, radians in [−π/2, π/2].
    fn datan(self) -> f64;
    /// Four-quadrant arctangent of `self / x` (`self` is y), radians in [−π, π].
    fn datan2(self, x: f64) -> f64;
    /// e^self.
    fn dexp(self) -> f64;
    /// e^self − 1, exact near 0.
    fn dexp_m1(self) -> f64;
    /// Natural logarithm.
    fn dln(self) -> f64;
    /// Base-2 logarithm.
    fn dlog2(self) -> f64;
    /// self^y.
    fn dpowf(self, y: f64) -> f64;
    /// Cube root.
    fn dcbrt(self) -> f64;
    /// √(self² + y²) without overflow.
    fn dhypot(self, y: f64) -> f64;
}

impl Det for f64 {
    fn dsin(self) -> f64 {
        libm::sin(self)
    }
    fn dcos(self) -> f64 {
        libm::cos(self)
    }
    fn dtan(self) -> f64 {
        libm::tan(self)
    }
    fn dasin(self) -> f64 {
        libm::asin(self)
    }
    fn dacos(self) -> f64 {
        libm::acos(self)
    }
    fn datan(self) -> f64 {
        libm::atan(self)
    }
    fn datan2(self, x: f64) -> f64 {
        libm::atan2(self, x)
    }
    fn dexp(self) -> f64 {
        libm::exp(self)
    }
    fn dexp_m1(self) -> f64 {
        libm::expm1(self)
    }
    fn dln(self) -> f64 {
        libm::log(self)
    }
    fn dlog2(self) -> f64 {
        libm::log2(self)
    }
    fn dpowf(self, y: f64) -> f64 {
        libm::pow(self, y)
    }
    fn dcbrt(self) -> f64 {
        libm::cbrt(self)
    }
    fn dhypot(self, y: f64) -> f64 {
        libm::hypot(self, y)
    }
}

#[cfg(test)]
mod tests {
    use super::Det;

    /// The bits these functions give here must be the correctly rounded values (computed with
    /// mpmath at 200 bits): a platform library may be off by an ulp, this code may not change.
    #[test]
    fn known_bits() {
        type Unary = fn(f64) -> f64;
        let cases: [(f64, Unary); 6] = [
            (0.5, |x| x.dsin()),
            (0.5, |x| x.dcos()),
            (1e22, |x| x.dsin()),
            (0.7, |x| x.datan2(0.3)),
            (1.5, |x| x.dexp()),
            (10.0, |x| x.dln()),
        ];
        let got: Vec<u64> = cases.iter().map(|(x, f)| f(*x).to_bits()).collect();
        let want: Vec<u64> = vec![
            0x3fde_aee8_744b_05f0,
            0x3fec_1528_065b_7d50,
            0xbfeb_453a_b76b_f397,
            0x3ff2_a78b_84fb_f5fc,
            0x4011_ed3f_e64f_c541,
            0x4002_6bb1_bbb5_5516,
        ];
        assert_eq!(got, want);
    }
}
