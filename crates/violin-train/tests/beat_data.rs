//! beat-net's corpus loaders: the train and validation split of one corpus, and the train
//! split alone of another (`train_beats --extra-train`).

use corpus::manifest::Split;
use violin_train::beat_data::{load_beat_corpus, load_beat_train_split};

mod common;

#[test]
fn the_extra_train_split_holds_only_training_items() {
    let dir = tempfile::tempdir().unwrap();
    common::build_tiny_corpus(dir.path(), 0);
    let manifest: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("manifest.json")).unwrap())
            .unwrap();
    let split_of = |name: &str| {
        manifest["items"]
            .as_array()
            .unwrap()
            .iter()
            .find(|it| it["dir"] == name)
            .map(|it| it["split"].as_str().unwrap().to_string())
            .unwrap()
    };
    let both = load_beat_corpus(dir.path(), &|_, _| {}).unwrap();
    let train = load_beat_train_split(dir.path(), &|_, _| {}).unwrap();
    assert!(!train.is_empty() && !both.val.is_empty());
    // The same recordings, in the same order, as the train split of the full loader.
    let names: Vec<&str> = train.iter().map(|r| r.name.as_str()).collect();
    let expected: Vec<&str> = both.train.iter().map(|r| r.name.as_str()).collect();
    assert_eq!(names, expected);
    let train_name = serde_json::to_value(Split::Train).unwrap();
    for r in &train {
        assert_eq!(serde_json::Value::String(split_of(&r.name)), train_name);
        assert_eq!(
            r.features,
            both.train[names.iter().position(|n| *n == r.name).unwrap()].features
        );
    }
    for r in &both.val {
        assert!(
            !names.contains(&r.name.as_str()),
            "{} is a validation item",
            r.name
        );
    }

    // A corpus without training items (as one written with --validation-violin) is refused.
    let path = dir.path().join("manifest.json");
    let mut relabelled = manifest.clone();
    for it in relabelled["items"].as_array_mut().unwrap() {
        if it["split"] == train_name {
            it["split"] = serde_json::to_value(Split::Val).unwrap();
        }
    }
    std::fs::write(&path, serde_json::to_string(&relabelled).unwrap()).unwrap();
    let e = load_beat_train_split(dir.path(), &|_, _| {})
        .unwrap_err()
        .to_string();
    assert!(e.contains("no train items"), "{e}");

    // A folder that is not a corpus is an error naming it.
    let empty = tempfile::tempdir().unwrap();
    let e = load_beat_train_split(empty.path(), &|_, _| {})
        .unwrap_err()
        .to_string();
    assert!(e.contains(&empty.path().display().to_string()), "{e}");
}
