//! Simple or compound metre from where notes fall inside the beats: in 6/8 the notes between
//! two beats sit at thirds, in 2/4 at halves and quarters.

/// Subdivisions per beat (3 for compound metres, otherwise 2) from note onsets relative to
/// the beats; 2 when the notes do not say.
///
/// ```
/// let beats: Vec<f64> = (0..20).map(|k| k as f64).collect();
/// let thirds: Vec<f64> = (0..57).map(|k| k as f64 / 3.0).collect();
/// assert_eq!(beat_track::subdivisions(&beats, &thirds), 3);
/// let halves: Vec<f64> = (0..38).map(|k| k as f64 / 2.0).collect();
/// assert_eq!(beat_track::subdivisions(&beats, &halves), 2);
/// assert_eq!(beat_track::subdivisions(&[], &halves), 2);
/// ```
pub fn subdivisions(beats_s: &[f64], onsets_s: &[f64]) -> u8 {
    let (mut triple, mut duple) = (0usize, 0usize);
    for w in beats_s.windows(2) {
        let (a, b) = (w[0], w[1]);
        if b - a <= 0.0 {
            continue;
        }
        let lo = onsets_s.partition_point(|&o| o < a);
        for &o in onsets_s[lo..].iter().take_while(|&&o| o < b) {
            let phase = (o - a) / (b - a);
            let near = |x: f64| (phase - x).abs() < 0.07;
            if near(1.0 / 3.0) || near(2.0 / 3.0) {
                triple += 1;
            } else if near(0.5) || near(0.25) || near(0.75) {
                duple += 1;
            }
        }
    }
    if triple >= 4 && triple as f64 > 1.2 * duple as f64 {
        3
    } else {
        2
    }
}
