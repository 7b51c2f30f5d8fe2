//! A minimal SoundFont 2 writer: looped samples, each over a key range, in one instrument
//! under one preset.
//!
//! It exists so the SoundFont renderer can be tested with no system package (the test
//! SoundFont is made by our own code: a bowed-string-like looped wave at GM program 40), and
//! so that sample sets in other formats (GUS patches, [`crate::render::sf2_from_gus_patch`])
//! can be played by the same renderer.

/// One sample of a [`write_sf2`] instrument: 16-bit mono, looped from `loop_start` to
/// `loop_end` (sample indices within `data`), played for the keys `key_lo..=key_hi`.
#[derive(Debug, Clone, PartialEq)]
pub struct Sf2Sample {
    /// The samples.
    pub data: Vec<i16>,
    /// Sample rate of `data`, Hz.
    pub rate_hz: u32,
    /// The MIDI key the sample sounds at when played unchanged.
    pub root_key: u8,
    /// Cents to add on playback to correct the sample's pitch (−50..=50).
    pub pitch_correction_cents: i8,
    /// First sample of the loop.
    pub loop_start: u32,
    /// One past the loop's last sample.
    pub loop_end: u32,
    /// Lowest key the sample plays.
    pub key_lo: u8,
    /// Highest key the sample plays.
    pub key_hi: u8,
}

/// Bytes of an SF2 whose preset `program` (bank 0) is one instrument playing `samples`,
/// each over its key range with a continuous loop, a 31 ms attack and a 100 ms release.
pub fn write_sf2(name: &[u8], program: u16, samples: &[Sf2Sample]) -> Vec<u8> {
    // Every sample is followed by 46 zero samples (SF2 2.01, 7.10).
    let mut smpl: Vec<u8> = Vec::new();
    let mut shdr = Vec::new();
    let mut igen = Vec::new();
    let mut ibag = Vec::new();
    for (k, s) in samples.iter().enumerate() {
        let start = (smpl.len() / 2) as u32;
        smpl.extend(s.data.iter().flat_map(|v| v.to_le_bytes()));
        smpl.extend([0u8; 92]);
        let n = s.data.len() as u32;
        shdr.push(sample_header(
            b"sample",
            [
                start,
                start + n,
                start + s.loop_start.min(n),
                start + s.loop_end.min(n),
                s.rate_hz,
            ],
            s.root_key,
            s.pitch_correction_cents,
        ));
        ibag.push(bag((igen.len() / 4) as u16, 0));
        igen.extend(
            [
                gen(43, u16::from_le_bytes([s.key_lo, s.key_hi])), // keyRange
                gen(34, (-6000i16) as u16),                        // attackVolEnv ≈ 31 ms
                gen(38, (-4000i16) as u16),                        // releaseVolEnv ≈ 100 ms
                gen(54, 1),                                        // sampleModes: loop
                gen(53, k as u16),                                 // sampleID (last)
            ]
            .concat(),
        );
    }
    ibag.push(bag((igen.len() / 4) as u16, 0));
    igen.extend(gen(0, 0));
    shdr.push(sample_header(b"EOS", [0; 5], 0, 0));
    let info = list(
        b"INFO",
        &[
            chunk(b"ifil", &[2, 0, 1, 0]),
            chunk(b"isng", b"EMU8000\0"),
            chunk(b"INAM", b"violin-skeleton\0"),
        ],
    );
    let sdta = list(b"sdta", &[chunk(b"smpl", &smpl)]);
    let phdr = [
        preset_header(name, program, 0, 0),
        preset_header(b"EOP", 0, 0, 1),
    ]
    .concat();
    let pbag = [bag(0, 0), bag(1, 0)].concat();
    let pgen = [gen(41, 0), gen(0, 0)].concat(); // instrument 0
    let inst = [
        inst_header(name, 0),
        inst_header(b"EOI", samples.len() as u16),
    ]
    .concat();
    let pdta = list(
        b"pdta",
        &[
            chunk(b"phdr", &phdr),
            chunk(b"pbag", &pbag),
            chunk(b"pmod", &[0u8; 10]),
            chunk(b"pgen", &pgen),
            chunk(b"inst", &inst),
            chunk(b"ibag", &ibag.concat()),
            chunk(b"imod", &[0u8; 10]),
            chunk(b"igen", &igen),
            chunk(b"shdr", &shdr.concat()),
        ],
    );
    let body = [b"sfbk".to_vec(), info, sdta, pdta].concat();
    [
        b"RIFF".to_vec(),
        (body.len() as u32).to_le_bytes().to_vec(),
        body,
    ]
    .concat()
}

/// Bytes of a tiny SF2 with a looped, bowed-string-like wave as GM program 40 ("Violin"),
/// bank 0, covering every key. About 5 KB.
///
/// ```
/// let sf2 = corpus::render::tiny_violin_sf2();
/// assert_eq!(&sf2[0..4], b"RIFF");
/// assert_eq!(&sf2[8..12], b"sfbk");
/// ```
pub fn tiny_violin_sf2() -> Vec<u8> {
    const CYCLE: usize = 256;
    const CYCLES: usize = 8;
    let data: Vec<i16> = (0..CYCLE * CYCLES)
        .map(|i| {
            let phase = std::f64::consts::TAU * (i % CYCLE) as f64 / CYCLE as f64;
            let v: f64 = (1..=24)
                .map(|h| (h as f64 * phase).sin() / (h as f64).powf(1.3))
                .sum();
            (v * 9_000.0) as i16
        })
        .collect();
    let n = data.len() as u32;
    let sample = Sf2Sample {
        data,
        rate_hz: (CYCLE as u32) * 220,
        root_key: 57, // A3, 220 Hz
        pitch_correction_cents: 0,
        loop_start: 0,
        loop_end: n,
        key_lo: 0,
        key_hi: 127,
    };
    write_sf2(b"Violin", 40, &[sample])
}

fn chunk(id: &[u8; 4], data: &[u8]) -> Vec<u8> {
    let mut out = id.to_vec();
    out.extend((data.len() as u32).to_le_bytes());
    out.extend(data);
    if data.len() % 2 == 1 {
        out.push(0);
    }
    out
}

fn list(kind: &[u8; 4], chunks: &[Vec<u8>]) -> Vec<u8> {
    let body = [kind.to_vec(), chunks.concat()].concat();
    [
        b"LIST".to_vec(),
        (body.len() as u32).to_le_bytes().to_vec(),
        body,
    ]
    .concat()
}

fn name20(name: &[u8]) -> Vec<u8> {
    let mut v = name.to_vec();
    v.resize(20, 0);
    v
}

fn preset_header(name: &[u8], preset: u16, bank: u16, bag_index: u16) -> Vec<u8> {
    let mut v = name20(name);
    for x in [preset, bank, bag_index] {
        v.extend(x.to_le_bytes());
    }
    v.extend([0u8; 12]); // library, genre, morphology
    v
}

fn inst_header(name: &[u8], bag_index: u16) -> Vec<u8> {
    let mut v = name20(name);
    v.extend(bag_index.to_le_bytes());
    v
}

fn bag(gen_index: u16, mod_index: u16) -> Vec<u8> {
    [gen_index.to_le_bytes(), mod_index.to_le_bytes()].concat()
}

fn gen(oper: u16, amount: u16) -> Vec<u8> {
    [oper.to_le_bytes(), amount.to_le_bytes()].concat()
}

fn sample_header(
    name: &[u8],
    [start, end, loop_start, loop_end, rate]: [u32; 5],
    key: u8,
    correction: i8,
) -> Vec<u8> {
    let mut v = name20(name);
    for x in [start, end, loop_start, loop_end, rate] {
        v.extend(x.to_le_bytes());
    }
    v.push(key);
    v.push(correction as u8);
    v.extend(0u16.to_le_bytes()); // sample link
    v.extend(if rate == 0 { 0u16 } else { 1u16 }.to_le_bytes()); // mono
    v
}
