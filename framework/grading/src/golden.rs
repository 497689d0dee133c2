use std::path::Path;

use glam::{Vec2, Vec3};
use serde::{Deserialize, Serialize, de::DeserializeOwned};

use raylab_core::Error;

/// One recorded input and the reference's output for it.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct GoldenCase<I, O> {
    /// The input.
    pub input: I,
    /// What the reference returned.
    pub expected: O,
}

/// A file of golden cases for one exercise, written by the reference (`raylab golden`).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct GoldenFile<I, O> {
    /// Exercise the cases belong to.
    pub exercise: String,
    /// The cases.
    pub cases: Vec<GoldenCase<I, O>>,
}

impl<I: Serialize + DeserializeOwned, O: Serialize + DeserializeOwned> GoldenFile<I, O> {
    /// Records `f` (the reference) on every input.
    pub fn record(exercise: &str, inputs: &[I], f: impl Fn(&I) -> O) -> Self
    where
        I: Clone,
    {
        Self {
            exercise: exercise.to_string(),
            cases: inputs
                .iter()
                .map(|i| GoldenCase {
                    input: i.clone(),
                    expected: f(i),
                })
                .collect(),
        }
    }

    /// Reads a golden file.
    pub fn load(path: &Path) -> Result<Self, Error> {
        let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
        serde_json::from_str(&text).map_err(|e| Error::SceneFile {
            path: path.to_path_buf(),
            reason: format!("malformed golden data: {e}"),
        })
    }

    /// Writes it as pretty JSON (stable: the same cases give the same bytes).
    pub fn save(&self, path: &Path) -> Result<(), Error> {
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
        }
        let mut text = serde_json::to_string_pretty(self).map_err(|e| Error::Failed {
            what: "golden data".into(),
            reason: e.to_string(),
        })?;
        text.push('\n');
        std::fs::write(path, text).map_err(|e| Error::io(path, e))
    }
}

/// `Ok` when `got` is within `abs + rel·|expected|` of `expected` (NaN is never close).
pub fn compare_f32(what: &str, got: f32, expected: f32, abs: f32, rel: f32) -> Result<(), String> {
    if (got - expected).abs() <= abs + rel * expected.abs() {
        Ok(())
    } else {
        Err(format!("{what} is {got}, expected {expected}"))
    }
}

/// [`compare_f32`] per component.
pub fn compare_vec2(
    what: &str,
    got: Vec2,
    expected: Vec2,
    abs: f32,
    rel: f32,
) -> Result<(), String> {
    let close = (got - expected)
        .abs()
        .cmple(Vec2::splat(abs) + rel * expected.abs())
        .all();
    if close {
        Ok(())
    } else {
        Err(format!("{what} is {got}, expected {expected}"))
    }
}

/// [`compare_f32`] per component.
pub fn compare_vec3(
    what: &str,
    got: Vec3,
    expected: Vec3,
    abs: f32,
    rel: f32,
) -> Result<(), String> {
    let close = (got - expected)
        .abs()
        .cmple(Vec3::splat(abs) + rel * expected.abs())
        .all();
    if close {
        Ok(())
    } else {
        Err(format!("{what} is {got}, expected {expected}"))
    }
}
