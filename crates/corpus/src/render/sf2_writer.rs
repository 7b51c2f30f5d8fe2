//! A minimal SoundFont 2 writer: one looped sample, one instrument, one preset.
//!
//! It exists so the SoundFont renderer can be tested with no system package: the test
//! SoundFont is made by our own code (a bowed-string-like looped wave at GM program 40).

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
    const ROOT_KEY: u8 = 57; // A3, 220 Hz
    let sample_rate = (CYCLE as u32) * 220;
    let n = CYCLE * CYCLES;
    let mut wave: Vec<i16> = (0..n)
        .map(|i| {
            let phase = std::f64::consts::TAU * (i % CYCLE) as f64 / CYCLE as f64;
            let v: f64 = (1..=24)
                .map(|h| (h as f64 * phase).sin() / (h as f64).powf(1.3))
                .sum();
            (v * 9_000.0) as i16
        })
        .collect();
    wave.extend(std::iter::repeat_n(0i16, 46));
    let smpl: Vec<u8> = wave.iter().flat_map(|s| s.to_le_bytes()).collect();

    let info = list(
        b"INFO",
        &[
            chunk(b"ifil", &[2, 0, 1, 0]),
            chunk(b"isng", b"EMU8000\0"),
            chunk(b"INAM", b"violin-skeleton test\0\0"),
        ],
    );
    let sdta = list(b"sdta", &[chunk(b"smpl", &smpl)]);

    let phdr = [
        preset_header(b"Violin", 40, 0, 0),
        preset_header(b"EOP", 0, 0, 1),
    ]
    .concat();
    let pbag = [bag(0, 0), bag(1, 0)].concat();
    let pmod = vec![0u8; 10];
    let pgen = [gen(41, 0), gen(0, 0)].concat(); // instrument 0
    let inst = [inst_header(b"Violin", 0), inst_header(b"EOI", 1)].concat();
    let ibag = [bag(0, 0), bag(6, 0)].concat();
    let imod = vec![0u8; 10];
    let igen = [
        gen(43, u16::from_le_bytes([0, 127])), // keyRange 0..127
        gen(34, (-6000i16) as u16),            // attackVolEnv ≈ 31 ms
        gen(38, (-4000i16) as u16),            // releaseVolEnv ≈ 100 ms
        gen(54, 1),                            // sampleModes: continuous loop
        gen(58, u16::from(ROOT_KEY)),          // overridingRootKey
        gen(53, 0),                            // sampleID (last)
        gen(0, 0),
    ]
    .concat();
    let shdr = [
        sample_header(b"wave", 0, n as u32, 0, n as u32, sample_rate, ROOT_KEY),
        sample_header(b"EOS", 0, 0, 0, 0, 0, 0),
    ]
    .concat();
    let pdta = list(
        b"pdta",
        &[
            chunk(b"phdr", &phdr),
            chunk(b"pbag", &pbag),
            chunk(b"pmod", &pmod),
            chunk(b"pgen", &pgen),
            chunk(b"inst", &inst),
            chunk(b"ibag", &ibag),
            chunk(b"imod", &imod),
            chunk(b"igen", &igen),
            chunk(b"shdr", &shdr),
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
    start: u32,
    end: u32,
    loop_start: u32,
    loop_end: u32,
    rate: u32,
    key: u8,
) -> Vec<u8> {
    let mut v = name20(name);
    for x in [start, end, loop_start, loop_end, rate] {
        v.extend(x.to_le_bytes());
    }
    v.push(key);
    v.push(0); // pitch correction
    v.extend(0u16.to_le_bytes()); // sample link
    v.extend(if rate == 0 { 0u16 } else { 1u16 }.to_le_bytes()); // mono
    v
}
