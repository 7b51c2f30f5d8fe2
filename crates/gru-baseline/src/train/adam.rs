//! Adam (Kingma & Ba) with global gradient-norm clipping, whose moments can be saved and
//! restored (for `--resume`).

use candle_core::backprop::GradStore;
use candle_core::{Tensor, Var};

use crate::error::{GruError, Result};

/// Adam over named variables.
#[derive(Debug)]
pub struct Adam {
    vars: Vec<(String, Var)>,
    m: Vec<Tensor>,
    v: Vec<Tensor>,
    step: u64,
    /// Learning rate.
    pub learning_rate: f64,
    beta1: f64,
    beta2: f64,
    eps: f64,
}

impl Adam {
    /// Adam with β = (0.9, 0.999), ε = 1e-8 over `vars` (sorted by name for a stable order).
    pub fn new(mut vars: Vec<(String, Var)>, learning_rate: f64) -> Result<Self> {
        vars.sort_by(|a, b| a.0.cmp(&b.0));
        let m = vars
            .iter()
            .map(|(_, v)| v.zeros_like())
            .collect::<candle_core::Result<Vec<_>>>()?;
        let v = vars
            .iter()
            .map(|(_, v)| v.zeros_like())
            .collect::<candle_core::Result<Vec<_>>>()?;
        Ok(Self {
            vars,
            m,
            v,
            step: 0,
            learning_rate,
            beta1: 0.9,
            beta2: 0.999,
            eps: 1e-8,
        })
    }

    /// Updates taken so far.
    pub fn steps_taken(&self) -> u64 {
        self.step
    }

    /// One update from `grads`, after scaling all gradients so their global L2 norm is at
    /// most `clip_norm` (when given). Returns the norm before clipping.
    pub fn step(&mut self, grads: &GradStore, clip_norm: Option<f64>) -> Result<f64> {
        let mut sq = 0f64;
        let mut gs = Vec::with_capacity(self.vars.len());
        for (_, var) in &self.vars {
            let g = grads.get(var.as_tensor()).cloned();
            if let Some(g) = &g {
                sq += f64::from(g.sqr()?.sum_all()?.to_scalar::<f32>()?);
            }
            gs.push(g);
        }
        let norm = sq.sqrt();
        if !norm.is_finite() {
            return Err(GruError::Config(
                "the gradient became NaN or infinite; lower the learning rate".into(),
            ));
        }
        let scale = match clip_norm {
            Some(c) if norm > c => c / norm,
            _ => 1.0,
        };
        self.step += 1;
        let t = self.step as i32;
        let c1 = 1.0 - self.beta1.powi(t);
        let c2 = 1.0 - self.beta2.powi(t);
        for (i, g) in gs.into_iter().enumerate() {
            let Some(g) = g else { continue };
            let g = (g * scale)?;
            let m = ((&self.m[i] * self.beta1)? + (&g * (1.0 - self.beta1))?)?;
            let v = ((&self.v[i] * self.beta2)? + (g.sqr()? * (1.0 - self.beta2))?)?;
            let update = ((&m / c1)? / ((&v / c2)?.sqrt()? + self.eps)?)?;
            let var = &self.vars[i].1;
            var.set(&(var.as_tensor() - (update * self.learning_rate)?)?)?;
            self.m[i] = m;
            self.v[i] = v;
        }
        Ok(norm)
    }

    /// The moments as named tensors (`m.<name>`, `v.<name>`) and the step count.
    pub fn state(&self) -> (Vec<(String, Tensor)>, u64) {
        let mut out = Vec::with_capacity(2 * self.vars.len());
        for (i, (name, _)) in self.vars.iter().enumerate() {
            out.push((format!("m.{name}"), self.m[i].clone()));
            out.push((format!("v.{name}"), self.v[i].clone()));
        }
        (out, self.step)
    }

    /// Restores moments saved by [`Adam::state`]; every variable must be present with its
    /// shape.
    pub fn restore(&mut self, lookup: &dyn Fn(&str) -> Option<Tensor>, step: u64) -> Result<()> {
        for (i, (name, var)) in self.vars.iter().enumerate() {
            for (kind, slot) in [("m", &mut self.m[i]), ("v", &mut self.v[i])] {
                let key = format!("{kind}.{name}");
                let t = lookup(&key)
                    .ok_or_else(|| GruError::Config(format!("checkpoint lacks `{key}`")))?;
                if t.dims() != var.dims() {
                    return Err(GruError::Config(format!(
                        "checkpoint `{key}` has shape {:?}, expected {:?}",
                        t.dims(),
                        var.dims()
                    )));
                }
                *slot = t;
            }
        }
        self.step = step;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use candle_core::Device;

    #[test]
    fn minimises_a_quadratic() {
        let x = Var::new(&[3.0f32, -2.0], &Device::Cpu).unwrap();
        let mut opt = Adam::new(vec![("x".into(), x.clone())], 0.1).unwrap();
        for _ in 0..300 {
            let loss = x.as_tensor().sqr().unwrap().sum_all().unwrap();
            opt.step(&loss.backward().unwrap(), Some(10.0)).unwrap();
        }
        let v = x.as_tensor().to_vec1::<f32>().unwrap();
        assert!(v.iter().all(|a| a.abs() < 0.05), "{v:?}");
        assert_eq!(opt.steps_taken(), 300);
    }

    #[test]
    fn clipping_bounds_the_first_step() {
        // The first Adam step moves each coordinate by ~lr whatever the gradient, so check
        // the reported norm instead.
        let x = Var::new(&[300.0f32, 400.0], &Device::Cpu).unwrap();
        let mut opt = Adam::new(vec![("x".into(), x.clone())], 0.01).unwrap();
        let loss = x.as_tensor().sqr().unwrap().sum_all().unwrap();
        let norm = opt.step(&loss.backward().unwrap(), Some(1.0)).unwrap();
        assert!((norm - 1000.0).abs() < 1e-3);
    }
}
