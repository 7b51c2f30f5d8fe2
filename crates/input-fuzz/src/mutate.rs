//! A seeded byte mutator: the operators of AFL-style fuzzers (bit flips, interesting
//! integers, insertions, deletions, duplications, truncation, splices) plus tokens that
//! matter to the text formats (numbers at the edge of `f64`, brackets, quotes).

pub use net_core::rng::Rng;

/// A number in `0..n` (`0` when `n` is 0).
pub fn below(rng: &mut Rng, n: usize) -> usize {
    if n == 0 {
        0
    } else {
        (rng.next_u64() % n as u64) as usize
    }
}

const INTERESTING_32: [u32; 10] = [
    0,
    1,
    0x7F,
    0x80,
    0xFF,
    0xFFFF,
    0x7FFF_FFFF,
    0x8000_0000,
    0xFFFF_FFFF,
    0x0100_0000,
];

const TOKENS: [&[u8]; 16] = [
    b"NaN",
    b"-1e308",
    b"1e308",
    b"-0",
    b"99999999999999999999",
    b"-1",
    b"[",
    b"]",
    b"{",
    b"}",
    b"\"",
    b",",
    b"null",
    b"[[[[[[[[[[[[[[[[",
    b"\n",
    b"\xff\xfe",
];

/// One mutant of `seed`: 1 to 4 stacked operators; `other` is a second seed to splice from.
pub fn mutate(seed: &[u8], other: &[u8], rng: &mut Rng) -> Vec<u8> {
    let mut b = seed.to_vec();
    let rounds = 1 + below(rng, 4);
    for _ in 0..rounds {
        apply_one(&mut b, other, rng);
    }
    b
}

fn apply_one(b: &mut Vec<u8>, other: &[u8], rng: &mut Rng) {
    let len = b.len();
    match below(rng, 10) {
        // Flip a few bits.
        0 if len > 0 => {
            for _ in 0..1 + below(rng, 8) {
                let i = below(rng, len);
                b[i] ^= 1 << below(rng, 8);
            }
        }
        // A random byte.
        1 if len > 0 => {
            let i = below(rng, len);
            b[i] = rng.next_u64() as u8;
        }
        // An interesting 32-bit integer (little or big endian), e.g. a size in a header;
        // headers are near the start, so half the time aim at the first 64 bytes.
        2 if len >= 4 => {
            let span = if below(rng, 2) == 0 { len.min(64) } else { len };
            let i = below(rng, span.saturating_sub(3).max(1));
            let v = INTERESTING_32[below(rng, INTERESTING_32.len())];
            let bytes = if below(rng, 2) == 0 {
                v.to_le_bytes()
            } else {
                v.to_be_bytes()
            };
            b[i..i + 4].copy_from_slice(&bytes);
        }
        // Delete a range.
        3 if len > 1 => {
            let i = below(rng, len);
            let n = 1 + below(rng, (len - i).min(256));
            b.drain(i..i + n);
        }
        // Duplicate a range somewhere else.
        4 if len > 1 => {
            let i = below(rng, len);
            let n = 1 + below(rng, (len - i).min(256));
            let piece = b[i..i + n].to_vec();
            let at = below(rng, b.len() + 1);
            b.splice(at..at, piece);
        }
        // Truncate.
        5 => {
            let keep = below(rng, len + 1);
            b.truncate(keep);
        }
        // A text token.
        6 => {
            let t = TOKENS[below(rng, TOKENS.len())];
            let at = below(rng, len + 1);
            if below(rng, 2) == 0 || at + t.len() > len {
                b.splice(at..at, t.iter().copied());
            } else {
                b[at..at + t.len()].copy_from_slice(t);
            }
        }
        // Splice with the other seed.
        7 if !other.is_empty() => {
            let cut = below(rng, len + 1);
            let from = below(rng, other.len());
            b.truncate(cut);
            b.extend_from_slice(&other[from..]);
        }
        // Random bytes inserted.
        8 => {
            let at = below(rng, len + 1);
            let n = 1 + below(rng, 32);
            let fresh: Vec<u8> = (0..n).map(|_| rng.next_u64() as u8).collect();
            b.splice(at..at, fresh);
        }
        // Replace a digit run by a huge or negative number (text formats).
        _ => {
            if let Some(i) = (0..8)
                .map(|_| below(rng, len.max(1)))
                .find(|&i| i < len && b[i].is_ascii_digit())
            {
                let mut j = i;
                while j < len && (b[j].is_ascii_digit() || b[j] == b'.') {
                    j += 1;
                }
                let t: &[u8] = match below(rng, 4) {
                    0 => b"1e300",
                    1 => b"-5",
                    2 => b"4294967296",
                    _ => b"0",
                };
                b.splice(i..j, t.iter().copied());
            } else if len > 0 {
                let i = below(rng, len);
                b[i] = b[i].wrapping_add(1);
            }
        }
    }
}

/// A structure-aware mutant of a JSON seed: the seed stays valid JSON, and 1 to 4 of its
/// values are replaced by values a parser must still survive (huge, negative, zero, the
/// wrong type, empty or cut arrays, very deep nesting). Falls back to [`mutate`] when the
/// seed is not JSON.
pub fn mutate_json(seed: &[u8], other: &[u8], rng: &mut Rng) -> Vec<u8> {
    let Ok(mut value) = serde_json::from_slice::<serde_json::Value>(seed) else {
        return mutate(seed, other, rng);
    };
    let rounds = 1 + below(rng, 4);
    for _ in 0..rounds {
        let count = count_nodes(&value);
        let target = below(rng, count);
        let mut seen = 0;
        mutate_node(&mut value, target, &mut seen, rng);
    }
    serde_json::to_vec(&value).unwrap_or_else(|_| seed.to_vec())
}

fn count_nodes(v: &serde_json::Value) -> usize {
    1 + match v {
        serde_json::Value::Array(a) => a.iter().map(count_nodes).sum(),
        serde_json::Value::Object(o) => o.values().map(count_nodes).sum(),
        _ => 0,
    }
}

fn replacement(old: &serde_json::Value, rng: &mut Rng) -> serde_json::Value {
    use serde_json::{json, Value};
    match below(rng, 12) {
        0 => json!(1e300),
        1 => json!(-1e300),
        2 => json!(-1),
        3 => json!(0),
        4 => json!(4_294_967_296u64),
        5 => json!(u64::MAX),
        6 => Value::Null,
        7 => json!("NaN"),
        8 => json!([]),
        9 => json!({}),
        10 => match old {
            Value::Array(a) if !a.is_empty() => {
                // Cut or repeat the array.
                let mut a = a.clone();
                if below(rng, 2) == 0 {
                    a.truncate(below(rng, a.len()));
                } else {
                    let first = a[0].clone();
                    a.extend(std::iter::repeat_n(first, 1 + below(rng, 64)));
                }
                Value::Array(a)
            }
            Value::Number(n) => json!(n.as_f64().map_or(0.0, |x| x * 1e6 + 0.5)),
            _ => json!(0.5),
        },
        _ => {
            let mut deep = json!(1);
            for _ in 0..200 {
                deep = json!([deep]);
            }
            deep
        }
    }
}

/// Replaces node number `target` (pre-order) of `v`.
fn mutate_node(v: &mut serde_json::Value, target: usize, seen: &mut usize, rng: &mut Rng) -> bool {
    if *seen == target {
        *v = replacement(v, rng);
        return true;
    }
    *seen += 1;
    match v {
        serde_json::Value::Array(a) => a.iter_mut().any(|c| mutate_node(c, target, seen, rng)),
        serde_json::Value::Object(o) => o.values_mut().any(|c| mutate_node(c, target, seen, rng)),
        _ => false,
    }
}

/// Recomputes the CRC of every Ogg page that still parses, so that a mutant reaches the
/// Vorbis decoder instead of stopping at the page checksum.
pub fn fix_ogg_crc(bytes: &mut [u8]) {
    let mut table = [0u32; 256];
    for (i, entry) in table.iter_mut().enumerate() {
        let mut r = (i as u32) << 24;
        for _ in 0..8 {
            r = if r & 0x8000_0000 != 0 {
                (r << 1) ^ 0x04C1_1DB7
            } else {
                r << 1
            };
        }
        *entry = r;
    }
    let mut at = 0;
    while at + 27 <= bytes.len() {
        if &bytes[at..at + 4] != b"OggS" {
            at += 1;
            continue;
        }
        let segments = bytes[at + 26] as usize;
        let header = 27 + segments;
        if at + header > bytes.len() {
            return;
        }
        let body: usize = bytes[at + 27..at + header]
            .iter()
            .map(|&b| b as usize)
            .sum();
        let end = at + header + body;
        if end > bytes.len() {
            return;
        }
        bytes[at + 22..at + 26].fill(0);
        let crc = bytes[at..end].iter().fold(0u32, |c, &b| {
            (c << 8) ^ table[(((c >> 24) as u8) ^ b) as usize]
        });
        bytes[at + 22..at + 26].copy_from_slice(&crc.to_le_bytes());
        at = end;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn same_seed_same_mutants_and_they_differ_from_the_seed() {
        let seed: Vec<u8> = (0..200u8).collect();
        let run = |s| {
            let mut rng = Rng::new(s);
            (0..50)
                .map(|_| mutate(&seed, b"other", &mut rng))
                .collect::<Vec<_>>()
        };
        assert_eq!(run(7), run(7));
        assert_ne!(run(7), run(8));
        let changed = run(7)
            .iter()
            .filter(|m| m.as_slice() != seed.as_slice())
            .count();
        assert!(
            changed >= 45,
            "{changed} of 50 mutants differ from the seed"
        );
    }

    #[test]
    fn ogg_checksums_are_recomputed_as_the_format_defines() {
        // The seed's pages carry valid CRCs: zeroing and recomputing gives them back.
        let seed = include_bytes!("../../dsp-mel/tests/fixtures/audio/a440_44100_2ch.ogg");
        let mut b = seed.to_vec();
        b[22..26].fill(0);
        fix_ogg_crc(&mut b);
        assert_eq!(b, seed.to_vec());
    }

    #[test]
    fn json_mutants_stay_json_and_change() {
        let seed = br#"{"fps": 30, "frames": [[1.0, 2.0], [3.0, 4.0]], "name": "x"}"#;
        let mut rng = Rng::new(3);
        let mut changed = 0;
        for _ in 0..50 {
            let m = mutate_json(seed, b"", &mut rng);
            // Valid JSON, except that very deep nesting is past the parser's recursion limit.
            if let Err(e) = serde_json::from_slice::<serde_json::Value>(&m) {
                assert!(e.to_string().contains("recursion limit"), "{e}");
            }
            changed += usize::from(
                m != serde_json::to_vec(
                    &serde_json::from_slice::<serde_json::Value>(seed).unwrap(),
                )
                .unwrap(),
            );
        }
        assert!(changed >= 40, "{changed}");
    }
}
