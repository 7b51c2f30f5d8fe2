//! Writing a number with four decimals, as `format!("{v:.4}")` does, without the general
//! float formatter (which falls back to its slow exact algorithm on most angles): BVH frames
//! hold tens of thousands of such numbers per second of motion.

/// Appends `v` with exactly four decimals to `out`, like `{:.4}` (a negative value that
/// rounds to zero keeps its sign, `-0.0000`).
pub(crate) fn push_fixed4(out: &mut String, v: f64) {
    let x = v.abs() * 1e4;
    // Near a rounding tie the product's own rounding could pick the other neighbour than
    // the exact value does: those (rare) values, and large or non-finite ones, take the
    // general formatter. Below 1e12 the product is within 2^-13 of the exact value.
    let near_tie = (x - x.floor() - 0.5).abs() < 1e-3;
    if !v.is_finite() || x >= 1e12 || near_tie {
        // Writing to a String cannot fail.
        let _ = std::fmt::Write::write_fmt(out, format_args!("{v:.4}"));
        return;
    }
    let units = x.round() as u64;
    if v.is_sign_negative() {
        out.push('-');
    }
    let int = itoa_buf(units / 10_000);
    out.push_str(int.as_str());
    out.push('.');
    let frac = units % 10_000;
    for d in [1000, 100, 10, 1] {
        out.push(char::from(b'0' + ((frac / d) % 10) as u8));
    }
}

/// Writes one BVH frame line to `out`: the numbers of `row` with four decimals, separated
/// by spaces, built in the reused buffer `text`.
pub(crate) fn write_frame_line(
    out: &mut dyn std::io::Write,
    text: &mut String,
    row: &[f64],
) -> std::io::Result<()> {
    text.clear();
    for (i, v) in row.iter().enumerate() {
        if i > 0 {
            text.push(' ');
        }
        push_fixed4(text, *v);
    }
    text.push('\n');
    out.write_all(text.as_bytes())
}

/// The decimal digits of `n` (a small stack buffer).
fn itoa_buf(mut n: u64) -> Digits {
    let mut d = Digits {
        buf: [0; 20],
        start: 20,
    };
    loop {
        d.start -= 1;
        d.buf[d.start] = b'0' + (n % 10) as u8;
        n /= 10;
        if n == 0 {
            break;
        }
    }
    d
}

struct Digits {
    buf: [u8; 20],
    start: usize,
}

impl Digits {
    fn as_str(&self) -> &str {
        // Only ASCII digits are written.
        std::str::from_utf8(&self.buf[self.start..]).unwrap_or("0")
    }
}

#[cfg(test)]
mod tests {
    use super::push_fixed4;

    fn fixed(v: f64) -> String {
        let mut s = String::new();
        push_fixed4(&mut s, v);
        s
    }

    #[test]
    fn matches_the_standard_formatter() {
        for v in [
            0.0, -0.0, 1.0, -1.0, 0.00004, -0.00004, 0.00006, 179.99996, -359.12345, 12345.6789,
            1e13, -7.5e-5, 90.0,
        ] {
            assert_eq!(fixed(v), format!("{v:.4}"), "{v}");
        }
        // Seeded pseudo-random angles and positions over several magnitudes.
        let mut x: u64 = 0x9E37_79B9_7F4A_7C15;
        for i in 0..200_000 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let unit = (x >> 11) as f64 / (1u64 << 53) as f64;
            let v = (unit - 0.5) * [720.0, 2.0, 400.0, 1e6][i % 4];
            assert_eq!(fixed(v), format!("{v:.4}"), "{v}");
        }
        for v in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY, 1e15, -2e20] {
            assert_eq!(fixed(v), format!("{v:.4}"), "{v}");
        }
    }
}
