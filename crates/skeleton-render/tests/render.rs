//! GIF, PNG and HTML output of skeleton-render, decoded and inspected.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use ndarray::Array3;
use skeleton::Motion;
use skeleton_render::{
    player_json, render_png, write_gif, write_gif_file, write_html_player, write_html_player_file,
    write_png_frames, RenderConfig, RenderError,
};

/// A standing stick figure waving its right arm, with a violin and a bow, in a 640×360 image.
fn figure(frames: usize) -> Motion {
    let base: [[f32; 2]; 10] = [
        [330.0, 90.0],
        [320.0, 140.0],
        [270.0, 145.0],
        [250.0, 200.0],
        [220.0, 190.0],
        [370.0, 145.0],
        [390.0, 205.0],
        [440.0, 165.0],
        [300.0, 270.0],
        [340.0, 270.0],
    ];
    let joints = Array3::from_shape_fn((frames, 10, 2), |(t, j, c)| {
        let wave = if (3..=4).contains(&j) && c == 0 {
            (t as f32 / 4.0).sin() * 30.0
        } else {
            0.0
        };
        base[j][c] + wave
    });
    let inst = Array3::from_shape_fn((frames, 4, 2), |(t, i, c)| {
        let p = [
            [230.0 + (t as f32 / 4.0).sin() * 30.0, 200.0],
            [400.0, 120.0],
            [470.0, 160.0],
            [360.0, 150.0],
        ];
        p[i][c]
    });
    Motion::new(30.0, joints)
        .unwrap()
        .with_instrument(inst)
        .unwrap()
        .with_image_size(640, 360)
}

fn decode_gif(bytes: &[u8]) -> (u16, u16, Vec<Vec<u8>>) {
    let mut opts = gif::DecodeOptions::new();
    opts.set_color_output(gif::ColorOutput::RGBA);
    let mut dec = opts.read_info(bytes).unwrap();
    let (w, h) = (dec.width(), dec.height());
    let mut frames = Vec::new();
    while let Some(f) = dec.read_next_frame().unwrap() {
        frames.push(f.buffer.to_vec());
    }
    (w, h, frames)
}

#[test]
fn gif_has_the_right_size_and_frame_count() {
    let m = figure(90);
    let cfg = RenderConfig {
        width: 320,
        height: 180,
        fps_out: 15.0,
        ..RenderConfig::default()
    };
    let mut bytes = Vec::new();
    write_gif(&m, &mut bytes, &cfg).unwrap();
    let (w, h, frames) = decode_gif(&bytes);
    assert_eq!((w, h), (320, 180));
    assert_eq!(frames.len(), 45);
    // The first picture is full-size and shows the violin's colour, the bow and the background.
    assert_eq!(frames[0].len(), 320 * 180 * 4);
    let has = |rgb: [u8; 3]| frames[0].chunks_exact(4).any(|p| p[..3] == rgb);
    assert!(has([176, 96, 38]), "violin body");
    assert!(has([225, 210, 170]), "bow");
    assert!(has([24, 26, 32]), "background");
    // Full rate when asked, capped at the motion's rate.
    let mut all = Vec::new();
    write_gif(
        &m,
        &mut all,
        &RenderConfig {
            fps_out: 100.0,
            ..cfg
        },
    )
    .unwrap();
    assert_eq!(decode_gif(&all).2.len(), 90);
}

#[test]
fn gif_file_is_written_atomically_and_bad_inputs_fail() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("a.gif");
    write_gif_file(&figure(10), &path, &RenderConfig::default()).unwrap();
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    let empty = Motion::new(30.0, Array3::zeros((0, 10, 2))).unwrap();
    assert!(matches!(
        write_gif(&empty, Vec::new(), &RenderConfig::default()),
        Err(RenderError::EmptyMotion)
    ));
    let bad = RenderConfig {
        fps_out: f64::NAN,
        ..RenderConfig::default()
    };
    assert!(matches!(
        write_gif(&figure(3), Vec::new(), &bad),
        Err(RenderError::InvalidConfig(_))
    ));
    let nan = Motion::new(30.0, Array3::from_elem((3, 10, 2), f32::NAN)).unwrap();
    assert!(matches!(
        write_gif(&nan, Vec::new(), &RenderConfig::default()),
        Err(RenderError::NothingToFrame)
    ));
    assert!(write_gif_file(
        &figure(3),
        dir.path().join("no/such/dir.gif"),
        &RenderConfig::default()
    )
    .is_err());
}

#[test]
fn missing_points_are_skipped_not_fatal() {
    let mut m = figure(4);
    m.frames_mut()[[1, 3, 0]] = f32::NAN;
    let png = render_png(&m, 1, &RenderConfig::default()).unwrap();
    assert_eq!(&png[1..4], b"PNG");
}

#[test]
fn png_frames_fill_a_folder() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("frames");
    let mut calls = 0;
    let n = write_png_frames(
        &figure(30),
        &out,
        &RenderConfig {
            fps_out: 10.0,
            ..RenderConfig::default()
        },
        |_, _| calls += 1,
    )
    .unwrap();
    assert_eq!(n, 10);
    assert_eq!(calls, 10);
    let mut names: Vec<String> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    names.sort();
    assert_eq!(names.first().unwrap(), "frame_000000.png");
    assert_eq!(names.last().unwrap(), "frame_000009.png");
}

#[test]
fn a_reused_frames_folder_holds_only_the_new_run() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("frames");
    let at = |fps_out: f64| RenderConfig {
        fps_out,
        ..RenderConfig::default()
    };
    assert_eq!(
        write_png_frames(&figure(30), &out, &at(10.0), |_, _| {}).unwrap(),
        10
    );
    assert_eq!(
        write_png_frames(&figure(30), &out, &at(5.0), |_, _| {}).unwrap(),
        5
    );
    assert_eq!(
        std::fs::read_dir(&out).unwrap().count(),
        5,
        "no stale frames"
    );
    // A folder with the user's own files is never emptied.
    std::fs::write(out.join("notes.txt"), b"mine").unwrap();
    let err = write_png_frames(&figure(30), &out, &at(10.0), |_, _| {}).unwrap_err();
    assert!(err.to_string().contains("holds other files"), "{err}");
    assert_eq!(std::fs::read_dir(&out).unwrap().count(), 6);
    // Only the folder itself is left in the parent: no temporary folders.
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
}

#[test]
fn html_player_embeds_motion_and_audio() {
    let m = figure(6);
    let mut page = Vec::new();
    let audio = b"RIFF\0\0\0\0WAVEfmt ";
    write_html_player(&m, Some((audio, "audio/wav")), &mut page).unwrap();
    let page = String::from_utf8(page).unwrap();
    assert!(page.starts_with("<!DOCTYPE html>"));
    assert!(page.contains("<audio id=\"audio\" preload=\"auto\" src=\"data:audio/wav;base64,UklGRgAAAABXQVZFZm10IA==\"></audio>"));
    assert!(page.contains("\"width\":640,\"height\":360"));
    assert!(
        page.contains("[330.0,90.0,320.0,140.0"),
        "first frame's joints"
    );
    assert!(page.contains("window.seek = seek"));
    assert!(page.contains("URLSearchParams"));
    assert_eq!(page.matches("<script").count(), 2, "everything inline");
    // The JSON parses, with one entry per frame.
    let json: serde_json::Value = serde_json::from_str(&player_json(&m).unwrap()).unwrap();
    assert_eq!(json["frames"].as_array().unwrap().len(), 6);
    assert_eq!(
        json["instrument"].as_array().unwrap()[0]
            .as_array()
            .unwrap()
            .len(),
        8
    );
    // Without audio there is no audio element; a bad MIME type is refused.
    let mut silent = Vec::new();
    write_html_player(&m, None, &mut silent).unwrap();
    assert!(!String::from_utf8(silent).unwrap().contains("<audio"));
    assert!(matches!(
        write_html_player(&m, Some((audio, "audio/wav\" onload=\"x")), Vec::new()),
        Err(RenderError::InvalidMime(_))
    ));
    let dir = tempfile::tempdir().unwrap();
    write_html_player_file(&m, None, dir.path().join("p.html")).unwrap();
    assert!(dir.path().join("p.html").exists());
}
