//! Nested-array tracks of the JSON formats: writing a `(T, points, dims)` array, reading one
//! back with its columns named.

use std::path::Path;

use ndarray::{Array3, ArrayView1, ArrayView2, Axis};
use serde::ser::{SerializeSeq, Serializer};
use serde::Serialize;

use crate::error::{Result, SkeletonError};

/// A `(T, points, dims)` track serialised as nested arrays.
pub(crate) struct Track<'a>(pub(crate) &'a Array3<f32>);
struct Frame<'a>(ArrayView2<'a, f32>);
struct Point<'a>(ArrayView1<'a, f32>);

impl Serialize for Track<'_> {
    fn serialize<S: Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        s.collect_seq(self.0.axis_iter(Axis(0)).map(Frame))
    }
}
impl Serialize for Frame<'_> {
    fn serialize<S: Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        s.collect_seq(self.0.axis_iter(Axis(0)).map(Point))
    }
}
impl Serialize for Point<'_> {
    fn serialize<S: Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        let mut seq = s.serialize_seq(Some(self.0.len()))?;
        for v in self.0.iter() {
            seq.serialize_element(v)?;
        }
        seq.end()
    }
}

/// Nested arrays as read: `null` is kept so it can be reported as a non-finite value.
pub(crate) type RawTrack = Vec<Vec<Vec<Option<f64>>>>;

/// For each column of the file, the index of that name in `known`; every known name must
/// appear exactly once.
pub(crate) fn column_order(
    path: &Path,
    names: &[String],
    known: &[&'static str],
) -> Result<Vec<usize>> {
    let mut order = Vec::with_capacity(names.len());
    let mut seen = vec![false; known.len()];
    for name in names {
        let Some(i) = known.iter().position(|k| k == name) else {
            return Err(SkeletonError::UnknownJoint {
                path: path.to_path_buf(),
                name: name.clone(),
            });
        };
        if std::mem::replace(&mut seen[i], true) {
            return Err(SkeletonError::MissingJoint {
                path: path.to_path_buf(),
                name: name.clone(),
                problem: "listed twice".into(),
            });
        }
        order.push(i);
    }
    if let Some(i) = seen.iter().position(|s| !s) {
        return Err(SkeletonError::MissingJoint {
            path: path.to_path_buf(),
            name: known[i].into(),
            problem: "missing".into(),
        });
    }
    Ok(order)
}

/// Builds a `(T, points, dims)` array from a raw track whose point columns follow `order`.
pub(crate) fn to_track(
    path: &Path,
    field: &str,
    raw: &RawTrack,
    order: &[usize],
    names: &[&'static str],
    dims: usize,
) -> Result<Array3<f32>> {
    let mut out = Array3::zeros((raw.len(), order.len(), dims));
    for (t, frame) in raw.iter().enumerate() {
        if frame.len() != order.len() {
            return Err(SkeletonError::FileShape {
                path: path.to_path_buf(),
                what: format!(
                    "{field}: frame {t} has {} points, expected {} (one per name listed)",
                    frame.len(),
                    order.len()
                ),
            });
        }
        for (column, point) in frame.iter().enumerate() {
            let p = order[column];
            if point.len() != dims {
                return Err(SkeletonError::FileShape {
                    path: path.to_path_buf(),
                    what: format!(
                        "{field}: frame {t}, {} has {} values, expected {dims}",
                        names[p],
                        point.len()
                    ),
                });
            }
            for (c, v) in point.iter().enumerate() {
                let value = v.map(|x| x as f32).filter(|x| x.is_finite());
                let Some(value) = value else {
                    return Err(SkeletonError::NonFinite {
                        path: path.to_path_buf(),
                        location: format!(
                            "{field}: frame {t}, {}, coordinate {} ({})",
                            names[p],
                            ["x", "y", "z"][c.min(2)],
                            v.map_or("null".to_string(), |x| x.to_string())
                        ),
                    });
                };
                out[[t, p, c]] = value;
            }
        }
    }
    Ok(out)
}
