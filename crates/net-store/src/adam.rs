//! Adam (Kingma & Ba) with optional decoupled weight decay, whose moments can be saved in a
//! checkpoint and restored to resume training exactly.

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
        self.step += 1;
        let c = self.config;
        let t = self.step as i32;
        let bias1 = 1.0 - c.beta1.powi(t);
        let bias2 = 1.0 - c.beta2.powi(t);
        for (i, (_, p)) in self.params.iter().enumerate() {
            let Some(g) = grads.get(p.as_tensor()) else {
                continue;
            };
            // Gradients from candle's backward can still reference the forward graph;
            // detached moments keep every step's graph from being retained forever.
            let g = &g.detach();
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
