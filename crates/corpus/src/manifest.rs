//! `manifest.json`: what a corpus holds, how it was made, and its statistics.

use serde::{Deserialize, Serialize};

use crate::augment::Augmentation;
use crate::item::{CorpusItem, RendererKind};
use crate::perform::TimingDraw;
use crate::repertoire::SkippedScore;
use crate::stats::CorpusStats;
use crate::violins::ViolinInfo;

fn default_audio() -> String {
    "audio.wav".into()
}

/// Format version of `manifest.json`.
pub const MANIFEST_VERSION: u32 = 2;

/// Train / validation / test.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Split {
    /// Training items (80 %).
    Train,
    /// Validation items (10 %).
    Val,
    /// Test items (10 %).
    Test,
}

impl Split {
    /// Splits for `count` items: indices ending in 3 are test, in 7 validation, the rest
    /// training (80/10/10); a corpus of 3 or more items always has at least one test item
    /// (the last) and one validation item (the one before it).
    ///
    /// ```
    /// use corpus::manifest::Split;
    /// let s = Split::assign(3);
    /// assert_eq!(s, vec![Split::Train, Split::Val, Split::Test]);
    /// ```
    pub fn assign(count: usize) -> Vec<Split> {
        let mut splits: Vec<Split> = (0..count)
            .map(|i| match i % 10 {
                3 => Split::Test,
                7 => Split::Val,
                _ => Split::Train,
            })
            .collect();
        if count >= 3 {
            if !splits.contains(&Split::Test) {
                splits[count - 1] = Split::Test;
            }
            if !splits.contains(&Split::Val) {
                let i = (0..count)
                    .rev()
                    .find(|&i| splits[i] == Split::Train)
                    .unwrap_or(0);
                splits[i] = Split::Val;
            }
        }
        splits
    }
}

/// What a test item holds out.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Default, Serialize, Deserialize,
)]
#[serde(rename_all = "lowercase")]
pub enum HeldOut {
    /// Nothing: a training or validation item, or an in-distribution test item.
    #[default]
    None,
    /// A violin source training never heard.
    Violin,
    /// A work training never saw.
    Repertoire,
    /// Both.
    Both,
}

impl HeldOut {
    /// The evaluation set's name: "in-distribution", "held-out violin", ….
    pub fn set_name(self) -> &'static str {
        match self {
            HeldOut::None => "in-distribution",
            HeldOut::Violin => "held-out violin",
            HeldOut::Repertoire => "held-out repertoire",
            HeldOut::Both => "held-out both",
        }
    }
}

/// One item's entry.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ManifestItem {
    /// Item id (its index).
    pub id: usize,
    /// Folder relative to the corpus root.
    pub dir: String,
    /// Split.
    pub split: Split,
    /// Renderer used.
    pub renderer: RendererKind,
    /// Length in seconds.
    pub duration_s: f64,
    /// Meter, e.g. "3/4".
    pub meter: String,
    /// Nominal tempo in bpm.
    pub tempo_bpm: f64,
    /// Number of notes.
    pub notes: usize,
    /// Augmentation applied.
    pub augmentation: Augmentation,
    /// What this test item holds out (evaluation reports each set apart).
    #[serde(default)]
    pub held_out: HeldOut,
    /// Violin source (see [`crate::violins`]); the renderer's name in version-1 manifests.
    #[serde(default)]
    pub violin: String,
    /// The work the music comes from ("etude/…" for études).
    #[serde(default)]
    pub work: String,
    /// The score part and bars used.
    #[serde(default)]
    pub score: String,
    /// Where the music comes from and its licence.
    #[serde(default)]
    pub source: String,
    /// Licence of the music.
    #[serde(default)]
    pub license: String,
    /// The audio file inside the item folder.
    #[serde(default = "default_audio")]
    pub audio: String,
    /// How the performance was timed.
    #[serde(default)]
    pub timing: Option<TimingDraw>,
    /// The recording chain: room, microphones, noise, level, rate, lossy coding.
    #[serde(default)]
    pub recording: Option<crate::room::Recording>,
}

impl ManifestItem {
    /// The entry of item `index`, written as `audio` in its folder.
    pub fn of(
        index: usize,
        item: &CorpusItem,
        split: Split,
        held_out: HeldOut,
        violin: &str,
        audio: String,
    ) -> Self {
        Self {
            id: index,
            dir: format!("items/{index:05}"),
            split,
            renderer: item.renderer,
            duration_s: item.timeline.duration_s,
            meter: item.time_signature.to_string(),
            tempo_bpm: item.timeline.tempo_bpm,
            notes: item.timeline.notes.len(),
            augmentation: item.augmentation.clone(),
            held_out,
            violin: violin.into(),
            work: item.score.work.clone(),
            score: item.score.id.clone(),
            source: item.score.provenance.source.clone(),
            license: item.score.provenance.license.clone(),
            audio,
            timing: item.timing.clone(),
            recording: item.recording.clone(),
        }
    }

    /// Whether the music is a generated étude (its work is `etude/…`).
    pub fn is_etude(&self) -> bool {
        self.work.starts_with("etude/")
    }

    /// The evaluation set a report puts this item in: a test item by what it holds out
    /// ([`HeldOut::set_name`]); a validation item by its music, because validation's works
    /// are not training's (its violins are) — `"val works"` stands for held-out repertoire
    /// and `"val études"` for in-distribution music, so a choice made on validation can be
    /// read for each; a training item `"train"`.
    ///
    /// ```
    /// use corpus::manifest::{HeldOut, ManifestItem, Split};
    /// let json = r#"{"id": 7, "dir": "items/00007", "split": "val", "renderer": "soundfont",
    ///   "duration_s": 12.0, "meter": "3/8", "tempo_bpm": 96.0, "notes": 40,
    ///   "augmentation": {"sample_rate_hz": 44100, "tuning_cents": 0.0, "gain_db": 0.0,
    ///     "reverb_wet": 0.0, "reverb_rt60_s": 0.0, "noise_dbfs": -200.0},
    ///   "work": "essenFolksong/lot/0396"}"#;
    /// let mut item: ManifestItem = serde_json::from_str(json)?;
    /// assert_eq!(item.evaluation_set(), "val works");
    /// item.work = "etude/42".into();
    /// assert_eq!(item.evaluation_set(), "val études");
    /// (item.split, item.held_out) = (Split::Test, HeldOut::Both);
    /// assert_eq!(item.evaluation_set(), "held-out both");
    /// # Ok::<(), serde_json::Error>(())
    /// ```
    pub fn evaluation_set(&self) -> &'static str {
        match self.split {
            Split::Test => self.held_out.set_name(),
            Split::Val if self.is_etude() => "val études",
            Split::Val => "val works",
            Split::Train => "train",
        }
    }
}

/// The whole manifest.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    /// [`MANIFEST_VERSION`].
    pub version: u32,
    /// Corpus seed.
    pub seed: u64,
    /// Renderer choice: "builtin", "soundfont" or "mix".
    pub renderer: String,
    /// Items.
    pub items: Vec<ManifestItem>,
    /// Statistics over all items.
    pub stats: CorpusStats,
    /// Violin sources and their licences (many-violin corpora).
    #[serde(default)]
    pub violins: Vec<ViolinInfo>,
    /// Repertoire files that were not used, with the reason.
    #[serde(default)]
    pub skipped_scores: Vec<SkippedScore>,
    /// Double stops played (second notes rendered under the melody, see
    /// [`crate::double_stop`]).
    #[serde(default)]
    pub double_stops_played: usize,
    /// Written chord pitches not played: chords reduced to their top note where the second
    /// note is out of the hand's reach, and the third and fourth notes of larger chords.
    #[serde(default)]
    pub chord_pitches_dropped: usize,
}

impl Manifest {
    /// The item folders (`ManifestItem::dir`) of the études ([`ManifestItem::is_etude`]);
    /// every other item is an excerpt of a work.
    pub fn etude_dirs(&self) -> std::collections::BTreeSet<&str> {
        self.items
            .iter()
            .filter(|i| i.is_etude())
            .map(|i| i.dir.as_str())
            .collect()
    }
}
