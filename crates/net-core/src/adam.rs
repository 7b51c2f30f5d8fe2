//! Adam (Kingma & Ba) with optional decoupled weight decay and optional global gradient-norm
//! clipping, whose moments can be saved in a checkpoint and restored to resume training
//! exactly.

use std::collections::HashMap;

use candle_core::backprop::GradStore;
use candle_core::{Tensor, Var};

use crate::error::{Result, StoreError};

/// Adam's hyper-parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AdamConfig {
    /// Learning rate.
    pub learning_rate: f64,
    /// First-moment decay.
    pub beta1: f64,
    /// Second-moment decay.
    pub beta2: f64,
    /// Denominator floor.
    pub eps: f64,
    /// Decoupled weight decay (AdamW); 0 = plain Adam.
    pub weight_decay: f64,
}

impl Default for AdamConfig {
    fn default() -> Self {
        Self {
            learning_rate: 1e-3,
            beta1: 0.9,
            beta2: 0.999,
            eps: 1e-8,
            weight_decay: 0.0,
        }
    }
}

/// The optimizer over named parameters.
#[derive(Debug)]
pub struct Adam {
    params: Vec<(String, Var)>,
    m: Vec<Tensor>,
    v: Vec<Tensor>,
    step: u64,
    /// Hyper-parameters (the learning rate may be changed between steps).
    pub config: AdamConfig,
}

impl Adam {
    /// An optimizer for `params` (name, variable), with zero moments.
    pub fn new(params: Vec<(String, Var)>, config: AdamConfig) -> Result<Self> {
        let mut m = Vec::with_capacity(params.len());
        let mut v = Vec::with_capacity(params.len());
        for (_, p) in &params {
            m.push(p.as_tensor().zeros_like()?);
            v.push(p.as_tensor().zeros_like()?);
        }
        Ok(Self {
            params,
            m,
            v,
            step: 0,
            config,
        })
    }

    /// Steps taken so far.
    pub fn steps(&self) -> u64 {
        self.step
    }

    /// Back-propagates `loss` and takes one step.
    pub fn backward_step(&mut self, loss: &Tensor) -> Result<()> {
        let grads = loss.backward()?;
        self.step(&grads)
    }

    /// One update from `grads` (parameters without a gradient are left alone).
    pub fn step(&mut self, grads: &GradStore) -> Result<()> {
        let gs: Vec<Option<Tensor>> = self
            .params
            .iter()
            .map(|(_, p)| grads.get(p.as_tensor()).cloned())
            .collect();
        self.update(gs, None)
    }

    /// One update from `grads` after scaling all gradients so that their global L2 norm is
    /// at most `clip_norm` (when given); returns the norm before clipping. A NaN or infinite
    /// norm is an error (and no parameter moves).
    ///
    /// ```
    /// use candle_core::{Device, Var};
    /// let x = Var::new(&[300.0f32, 400.0], &Device::Cpu)?;
    /// let mut opt = net_core::Adam::new(vec![("x".into(), x.clone())], Default::default())?;
    /// let loss = x.as_tensor().sqr()?.sum_all()?;
    /// let norm = opt.step_clipped(&loss.backward()?, Some(1.0))?;
    /// assert!((norm - 1000.0).abs() < 1e-3);
    /// # Ok::<(), net_core::StoreError>(())
    /// ```
    pub fn step_clipped(&mut self, grads: &GradStore, clip_norm: Option<f64>) -> Result<f64> {
        let mut sq = 0f64;
        let mut gs = Vec::with_capacity(self.params.len());
        for (_, p) in &self.params {
            let g = grads.get(p.as_tensor()).cloned();
            if let Some(g) = &g {
                sq += f64::from(g.sqr()?.sum_all()?.to_scalar::<f32>()?);
            }
            gs.push(g);
        }
        let norm = sq.sqrt();
        if !norm.is_finite() {
            return Err(StoreError::Config(
                "the gradient became NaN or infinite; lower the learning rate".into(),
            ));
        }
        let scale = match clip_norm {
            Some(c) if norm > c => Some(c / norm),
            _ => None,
        };
        self.update(gs, scale)?;
        Ok(norm)
    }

    /// The update itself: `grads[i]` is parameter `i`'s gradient, multiplied by `scale` when
    /// given.
    fn update(&mut self, grads: Vec<Option<Tensor>>, scale: Option<f64>) -> Result<()> {
        self.step += 1;
        let c = self.config;
        let t = self.step as i32;
        let bias1 = 1.0 - c.beta1.powi(t);
        let bias2 = 1.0 - c.beta2.powi(t);
        for (i, ((_, p), g)) in self.params.iter().zip(grads).enumerate() {
            let Some(g) = g else {
                continue;
            };
            // Gradients from candle's backward can still reference the forward graph;
            // detached moments keep every step's graph from being retained forever.
            let g = match scale {
                Some(s) => (g.detach() * s)?,
                None => g.detach(),
            };
            let g = &g;
            let m = ((&self.m[i] * c.beta1)? + (g * (1.0 - c.beta1))?)?;
            let v = ((&self.v[i] * c.beta2)? + (g.sqr()? * (1.0 - c.beta2))?)?;
            let m_hat = (&m / bias1)?;
            let denom = ((&v / bias2)?.sqrt()? + c.eps)?;
            let mut theta = p.as_tensor().detach();
            if c.weight_decay > 0.0 {
                theta = (&theta * (1.0 - c.learning_rate * c.weight_decay))?;
            }
            let update = (m_hat.div(&denom)? * c.learning_rate)?;
            p.set(&theta.sub(&update)?)?;
            self.m[i] = m;
            self.v[i] = v;
        }
        Ok(())
    }

    /// The state to checkpoint: `adam.m.NAME`, `adam.v.NAME` and `adam.step` (as f32 pairs of
    /// 24-bit halves, exact up to 2⁴⁸ steps).
    pub fn state(&self) -> Result<Vec<(String, Tensor)>> {
        let mut out = Vec::with_capacity(2 * self.params.len() + 1);
        for (i, (name, _)) in self.params.iter().enumerate() {
            out.push((format!("adam.m.{name}"), self.m[i].clone()));
            out.push((format!("adam.v.{name}"), self.v[i].clone()));
        }
        let hi = (self.step >> 24) as f32;
        let lo = (self.step & 0xFF_FFFF) as f32;
        out.push((
            "adam.step".to_string(),
            Tensor::new(&[hi, lo], &candle_core::Device::Cpu)?,
        ));
        Ok(out)
    }

    /// Restores [`Adam::state`]; every moment must be present with the parameter's shape.
    pub fn load_state(&mut self, tensors: &HashMap<String, Tensor>) -> Result<()> {
        let missing =
            |what: &str| StoreError::Config(format!("checkpoint has no optimizer tensor {what}"));
        for (i, (name, p)) in self.params.iter().enumerate() {
            for (kind, slot) in [("m", &mut self.m[i]), ("v", &mut self.v[i])] {
                let key = format!("adam.{kind}.{name}");
                let t = tensors.get(&key).ok_or_else(|| missing(&key))?;
                if t.dims() != p.as_tensor().dims() {
                    return Err(StoreError::Config(format!(
                        "checkpoint tensor {key} has shape {:?}, the parameter has {:?}",
                        t.dims(),
                        p.as_tensor().dims()
                    )));
                }
                *slot = t.clone();
            }
        }
        let step = tensors
            .get("adam.step")
            .ok_or_else(|| missing("adam.step"))?
            .to_vec1::<f32>()?;
        if let [hi, lo] = step.as_slice() {
            self.step = ((*hi as u64) << 24) | (*lo as u64);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use candle_core::Device;

    fn adam(x: &Var, learning_rate: f64) -> Adam {
        let config = AdamConfig {
            learning_rate,
            ..AdamConfig::default()
        };
        Adam::new(vec![("x".into(), x.clone())], config).unwrap()
    }

    #[test]
    fn minimises_a_quadratic() {
        let x = Var::new(&[3.0f32, -2.0], &Device::Cpu).unwrap();
        let mut opt = adam(&x, 0.1);
        for _ in 0..300 {
            let loss = x.as_tensor().sqr().unwrap().sum_all().unwrap();
            opt.step_clipped(&loss.backward().unwrap(), Some(10.0))
                .unwrap();
        }
        let v = x.as_tensor().to_vec1::<f32>().unwrap();
        assert!(v.iter().all(|a| a.abs() < 0.05), "{v:?}");
        assert_eq!(opt.steps(), 300);
    }

    #[test]
    fn clipping_bounds_the_first_step() {
        // The first Adam step moves each coordinate by ~lr whatever the gradient, so check
        // the reported norm instead.
        let x = Var::new(&[300.0f32, 400.0], &Device::Cpu).unwrap();
        let mut opt = adam(&x, 0.01);
        let loss = x.as_tensor().sqr().unwrap().sum_all().unwrap();
        let norm = opt
            .step_clipped(&loss.backward().unwrap(), Some(1.0))
            .unwrap();
        assert!((norm - 1000.0).abs() < 1e-3);
    }

    #[test]
    fn a_non_finite_gradient_is_refused_and_nothing_moves() {
        let x = Var::new(&[1.0f32, f32::NAN], &Device::Cpu).unwrap();
        let mut opt = adam(&x, 0.01);
        let loss = x.as_tensor().sqr().unwrap().sum_all().unwrap();
        let e = opt.step_clipped(&loss.backward().unwrap(), Some(1.0));
        assert!(e.unwrap_err().to_string().contains("NaN or infinite"));
        assert_eq!(opt.steps(), 0);
    }

    #[test]
    fn unclipped_and_plain_steps_agree() {
        let a = Var::new(&[0.5f32, -1.5], &Device::Cpu).unwrap();
        let b = Var::new(&[0.5f32, -1.5], &Device::Cpu).unwrap();
        let (mut oa, mut ob) = (adam(&a, 0.05), adam(&b, 0.05));
        for _ in 0..5 {
            let la = a.as_tensor().sqr().unwrap().sum_all().unwrap();
            let lb = b.as_tensor().sqr().unwrap().sum_all().unwrap();
            oa.step(&la.backward().unwrap()).unwrap();
            ob.step_clipped(&lb.backward().unwrap(), None).unwrap();
        }
        assert_eq!(
            a.as_tensor().to_vec1::<f32>().unwrap(),
            b.as_tensor().to_vec1::<f32>().unwrap()
        );
    }
}
