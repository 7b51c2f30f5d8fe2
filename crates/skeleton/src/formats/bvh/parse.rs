//! A small BVH reader and forward kinematics, enough to check exported files.

use crate::error::{Result, SkeletonError};
use crate::geometry::{Mat3, Vec3};

/// A BVH channel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Channel {
    /// Translation along x.
    Xposition,
    /// Translation along y.
    Yposition,
    /// Translation along z.
    Zposition,
    /// Rotation about x, degrees.
    Xrotation,
    /// Rotation about y, degrees.
    Yrotation,
    /// Rotation about z, degrees.
    Zrotation,
}

impl Channel {
    fn parse(token: &str) -> Option<Channel> {
        Some(match token {
            "Xposition" => Channel::Xposition,
            "Yposition" => Channel::Yposition,
            "Zposition" => Channel::Zposition,
            "Xrotation" => Channel::Xrotation,
            "Yrotation" => Channel::Yrotation,
            "Zrotation" => Channel::Zrotation,
            _ => return None,
        })
    }
}

/// One joint of a parsed hierarchy.
#[derive(Debug, Clone, PartialEq)]
pub struct BvhJoint {
    /// Name.
    pub name: String,
    /// Index of the parent joint (`None` for the root).
    pub parent: Option<usize>,
    /// Offset from the parent, file units.
    pub offset: [f64; 3],
    /// Channels in file order.
    pub channels: Vec<Channel>,
    /// The End Site offset, for leaf joints.
    pub end_site: Option<[f64; 3]>,
}

/// A parsed BVH file.
#[derive(Debug, Clone, PartialEq)]
pub struct Bvh {
    /// Joints, parents before children, in file order.
    pub joints: Vec<BvhJoint>,
    /// Seconds per frame.
    pub frame_time_s: f64,
    /// One row of channel values per frame.
    pub frames: Vec<Vec<f64>>,
}

struct Tokens<'a> {
    items: Vec<(usize, &'a str)>,
    at: usize,
}

impl<'a> Tokens<'a> {
    fn new(text: &'a str) -> Tokens<'a> {
        let items = text
            .lines()
            .enumerate()
            .flat_map(|(i, l)| l.split_whitespace().map(move |t| (i + 1, t)))
            .collect();
        Tokens { items, at: 0 }
    }

    fn line(&self) -> usize {
        self.items
            .get(self.at)
            .or(self.items.last())
            .map_or(0, |t| t.0)
    }

    fn err(&self, reason: impl Into<String>) -> SkeletonError {
        SkeletonError::BvhParse {
            line: self.line(),
            reason: reason.into(),
        }
    }

    fn next(&mut self) -> Result<&'a str> {
        let t = self
            .items
            .get(self.at)
            .map(|t| t.1)
            .ok_or_else(|| self.err("unexpected end of file"))?;
        self.at += 1;
        Ok(t)
    }

    fn expect(&mut self, want: &str) -> Result<()> {
        let got = self.next()?;
        if got == want {
            Ok(())
        } else {
            self.at -= 1;
            Err(self.err(format!("expected `{want}`, found `{got}`")))
        }
    }

    fn number(&mut self) -> Result<f64> {
        let t = self.next()?;
        t.parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| {
                self.at -= 1;
                self.err(format!("expected a number, found `{t}`"))
            })
    }

    fn vec3(&mut self) -> Result<[f64; 3]> {
        Ok([self.number()?, self.number()?, self.number()?])
    }
}

fn parse_joint(tok: &mut Tokens, parent: Option<usize>, joints: &mut Vec<BvhJoint>) -> Result<()> {
    let name = tok.next()?.to_string();
    tok.expect("{")?;
    tok.expect("OFFSET")?;
    let offset = tok.vec3()?;
    tok.expect("CHANNELS")?;
    let n = tok.number()?;
    if !(0.0..=6.0).contains(&n) || n.fract() != 0.0 {
        return Err(tok.err(format!("joint {name}: CHANNELS count {n} is not 0..=6")));
    }
    let mut channels = Vec::with_capacity(n as usize);
    for _ in 0..n as usize {
        let t = tok.next()?;
        channels.push(Channel::parse(t).ok_or_else(|| tok.err(format!("unknown channel `{t}`")))?);
    }
    let index = joints.len();
    joints.push(BvhJoint {
        name,
        parent,
        offset,
        channels,
        end_site: None,
    });
    loop {
        match tok.next()? {
            "JOINT" => parse_joint(tok, Some(index), joints)?,
            "End" => {
                tok.expect("Site")?;
                tok.expect("{")?;
                tok.expect("OFFSET")?;
                joints[index].end_site = Some(tok.vec3()?);
                tok.expect("}")?;
            }
            "}" => return Ok(()),
            other => {
                return Err(tok.err(format!("expected JOINT, End Site or `}}`, found `{other}`")))
            }
        }
    }
}

/// Parses BVH text: hierarchy, `Frames:`, `Frame Time:` and the channel values, checking
/// that every frame has one value per channel.
pub fn parse_bvh(text: &str) -> Result<Bvh> {
    let mut tok = Tokens::new(text);
    tok.expect("HIERARCHY")?;
    tok.expect("ROOT")?;
    let mut joints = Vec::new();
    parse_joint(&mut tok, None, &mut joints)?;
    tok.expect("MOTION")?;
    tok.expect("Frames:")?;
    let count = tok.number()?;
    if count < 0.0 || count.fract() != 0.0 {
        return Err(tok.err(format!("Frames: {count} is not a frame count")));
    }
    tok.expect("Frame")?;
    tok.expect("Time:")?;
    let frame_time_s = tok.number()?;
    if frame_time_s <= 0.0 {
        return Err(tok.err("Frame Time must be positive"));
    }
    let channels: usize = joints.iter().map(|j| j.channels.len()).sum();
    let mut frames = Vec::with_capacity(count as usize);
    for _ in 0..count as usize {
        let row = (0..channels)
            .map(|_| tok.number())
            .collect::<Result<Vec<f64>>>()?;
        frames.push(row);
    }
    if tok.at < tok.items.len() {
        return Err(tok.err(format!(
            "more values than {count} frames of {channels} channels"
        )));
    }
    Ok(Bvh {
        joints,
        frame_time_s,
        frames,
    })
}

impl Bvh {
    /// Total channels per frame.
    pub fn channel_count(&self) -> usize {
        self.joints.iter().map(|j| j.channels.len()).sum()
    }

    /// Index of the joint called `name`.
    pub fn joint_index(&self, name: &str) -> Option<usize> {
        self.joints.iter().position(|j| j.name == name)
    }

    /// World positions (file units) of every joint at `frame`: each joint's transform is its
    /// parent's, then its OFFSET plus position channels, then its rotation channels composed
    /// in file order. `None` for a frame out of range.
    pub fn forward_kinematics(&self, frame: usize) -> Option<Vec<[f64; 3]>> {
        let row = self.frames.get(frame)?;
        let mut rot = Vec::with_capacity(self.joints.len());
        let mut pos: Vec<Vec3> = Vec::with_capacity(self.joints.len());
        let mut k = 0;
        for j in &self.joints {
            let mut local_t = Vec3::new(j.offset[0], j.offset[1], j.offset[2]);
            let mut local_r = Mat3::IDENTITY;
            for c in &j.channels {
                let v = row[k];
                k += 1;
                match c {
                    Channel::Xposition => local_t.x += v,
                    Channel::Yposition => local_t.y += v,
                    Channel::Zposition => local_t.z += v,
                    Channel::Xrotation => local_r = local_r * Mat3::rot_x(v.to_radians()),
                    Channel::Yrotation => local_r = local_r * Mat3::rot_y(v.to_radians()),
                    Channel::Zrotation => local_r = local_r * Mat3::rot_z(v.to_radians()),
                }
            }
            let (r, p) = match j.parent {
                Some(p) => (rot[p] * local_r, pos[p] + rot[p] * local_t),
                None => (local_r, local_t),
            };
            rot.push(r);
            pos.push(p);
        }
        Some(pos.into_iter().map(Vec3::to_array).collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const TINY: &str = "HIERARCHY\nROOT A\n{\n OFFSET 0 0 0\n CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n JOINT B\n {\n  OFFSET 0 10 0\n  CHANNELS 3 Zrotation Xrotation Yrotation\n  End Site\n  {\n   OFFSET 0 5 0\n  }\n }\n}\nMOTION\nFrames: 2\nFrame Time: 0.0333333\n1 2 3 0 0 0 0 0 0\n0 0 0 90 0 0 0 0 0\n";

    #[test]
    fn parses_and_runs_forward_kinematics() {
        let b = parse_bvh(TINY).unwrap();
        assert_eq!(b.channel_count(), 9);
        assert_eq!(b.frames.len(), 2);
        assert!((b.frame_time_s - 0.0333333).abs() < 1e-12);
        assert_eq!(b.joints[1].end_site, Some([0.0, 5.0, 0.0]));
        let f0 = b.forward_kinematics(0).unwrap();
        assert_eq!(f0[1], [1.0, 12.0, 3.0]);
        // Root turned 90° about z: B's offset (0, 10, 0) points along −x.
        let f1 = b.forward_kinematics(1).unwrap();
        assert!((f1[1][0] + 10.0).abs() < 1e-9 && f1[1][1].abs() < 1e-9);
        assert!(b.forward_kinematics(2).is_none());
    }

    #[test]
    fn malformed_files_name_the_line() {
        let truncated = &TINY[..TINY.len() - 10];
        let e = parse_bvh(truncated).unwrap_err().to_string();
        assert!(e.contains("BVH line"), "{e}");
        let bad = TINY.replace("Yrotation\n  End", "Wrotation\n  End");
        assert!(parse_bvh(&bad)
            .unwrap_err()
            .to_string()
            .contains("unknown channel"));
        let extra = format!("{TINY}7\n");
        assert!(parse_bvh(&extra).is_err());
        assert!(parse_bvh("").is_err());
    }
}
