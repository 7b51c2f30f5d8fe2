//! Truncated back-propagation through time: each epoch, the training sequences are dealt to
//! `B` parallel streams and cut into consecutive windows; a stream's GRU state is carried
//! (detached) from one window to the next of the same sequence and reset to zero when a new
//! sequence starts, so training sees the same long-context state as chunked inference.

use net_core::rng::Rng;

/// One window of one sequence.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Window {
    /// Index of the sequence.
    pub seq: usize,
    /// First frame.
    pub start: usize,
    /// Frames (≤ the window length; the last window of a sequence may be shorter).
    pub len: usize,
    /// First window of this pass over the sequence: the state starts at zero.
    pub first: bool,
}

/// The windows of one epoch: `steps[s][b]` is stream `b`'s window at step `s` (`None` when
/// the stream has run out). Sequences are shuffled; each starts at a random phase in
/// `[0, window / 2)` (frames before it are skipped this epoch), so window boundaries move
/// from epoch to epoch; streams are balanced by window count.
///
/// ```
/// let mut rng = net_core::rng::Rng::new(1);
/// let steps = gru_baseline::train::plan_epoch(&[100, 40], 30, 2, &mut rng);
/// let windows: usize = steps.iter().flatten().flatten().count();
/// assert!(windows >= 4);
/// assert!(steps.iter().flatten().flatten().all(|w| w.len <= 30));
/// ```
pub fn plan_epoch(
    lengths: &[usize],
    window: usize,
    batch: usize,
    rng: &mut Rng,
) -> Vec<Vec<Option<Window>>> {
    let window = window.max(1);
    let batch = batch.max(1);
    let mut order: Vec<usize> = (0..lengths.len()).collect();
    for i in (1..order.len()).rev() {
        let j = (rng.next_u64() % (i as u64 + 1)) as usize;
        order.swap(i, j);
    }
    let mut streams: Vec<Vec<Window>> = vec![Vec::new(); batch];
    for &seq in &order {
        let len = lengths[seq];
        if len == 0 {
            continue;
        }
        let phase = if len > window && window >= 2 {
            (rng.next_u64() % (window as u64 / 2)) as usize
        } else {
            0
        };
        let target = (0..batch)
            .min_by_key(|&b| (streams[b].len(), b))
            .unwrap_or(0);
        let mut start = phase;
        let mut first = true;
        while start < len {
            let n = window.min(len - start);
            streams[target].push(Window {
                seq,
                start,
                len: n,
                first,
            });
            first = false;
            start += n;
        }
    }
    let steps = streams.iter().map(Vec::len).max().unwrap_or(0);
    (0..steps)
        .map(|s| streams.iter().map(|st| st.get(s).copied()).collect())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn covers_each_sequence_contiguously_after_its_phase() {
        let lengths = [95, 10, 61, 300, 0];
        let mut rng = Rng::new(3);
        let plan = plan_epoch(&lengths, 20, 3, &mut rng);
        for (seq, &len) in lengths.iter().enumerate() {
            let mut ws: Vec<(usize, Window)> = Vec::new();
            for (s, row) in plan.iter().enumerate() {
                for w in row.iter().flatten() {
                    if w.seq == seq {
                        ws.push((s, *w));
                    }
                }
            }
            if len == 0 {
                assert!(ws.is_empty());
                continue;
            }
            assert!(ws[0].1.first && ws[0].1.start < 10);
            assert!(ws.iter().skip(1).all(|(_, w)| !w.first));
            for pair in ws.windows(2) {
                assert_eq!(pair[0].1.start + pair[0].1.len, pair[1].1.start);
                assert_eq!(pair[0].0 + 1, pair[1].0, "consecutive steps on one stream");
            }
            let last = ws[ws.len() - 1].1;
            assert_eq!(last.start + last.len, len);
        }
    }

    #[test]
    fn same_seed_same_plan() {
        let a = plan_epoch(&[50, 70, 90], 16, 2, &mut Rng::new(9));
        let b = plan_epoch(&[50, 70, 90], 16, 2, &mut Rng::new(9));
        assert_eq!(a, b);
        assert!(plan_epoch(&[], 16, 2, &mut Rng::new(9)).is_empty());
    }
}
