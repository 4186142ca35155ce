//! A keyframe performance file (format "facesr-performance", version 1,
//! docs/performances.md) sampled into per-frame weights exactly as the engine
//! and the C sample (samples/c/performance.c) do: frame f at
//! t_first + f / fps up to the last keyframe, linear interpolation in f64, a
//! shape a keyframe does not list is 0 there. The same arithmetic is what
//! lets the three samples produce the same surfaces.
use crate::json::{self, Json};
use std::path::Path;

const MAX_FPS: f64 = 1000.0; // the engine's bounds
const MAX_FRAMES: f64 = 3e6;

#[derive(Debug)]
pub struct Performance {
    pub fps: f64,
    pub frames: usize,
    /// Every blendshape some keyframe lists, in order of first appearance.
    pub names: Vec<String>,
    /// frames × names.len(), row-major.
    pub weights: Vec<f32>,
    /// Explicit jaw transforms (not played, as in the C sample).
    pub has_jaw: bool,
}

impl Performance {
    /// Weights of frame `f`, one per name.
    pub fn frame(&self, f: usize) -> &[f32] {
        let n = self.names.len();
        &self.weights[f * n..(f + 1) * n]
    }

    /// Errors read "path: problem".
    pub fn load(path: &Path) -> Result<Performance, String> {
        let shown = path.display();
        let bytes = std::fs::read(path).map_err(|e| format!("{shown}: cannot read the performance file ({e})"))?;
        let root = json::parse(&bytes).map_err(|e| format!("{shown}: not valid JSON: {e}"))?;
        build(&root).map_err(|e| format!("{shown}: {e}"))
    }
}

fn number(v: Option<&Json>) -> Option<f64> {
    match v {
        Some(Json::Number(n)) => Some(*n),
        _ => None,
    }
}

fn build(root: &Json) -> Result<Performance, String> {
    if !matches!(root, Json::Object(_)) {
        return Err("is not a JSON object".into());
    }
    if !matches!(root.get("format"), Some(Json::String(s)) if s == "facesr-performance") {
        return Err("'format' is not \"facesr-performance\"".into());
    }
    if number(root.get("version")) != Some(1.0) {
        return Err("'version' is missing or not 1".into());
    }
    let fps = match number(root.get("fps")) {
        Some(f) if f > 0.0 && f <= MAX_FPS => f,
        _ => return Err("'fps' is missing or not in (0, 1000]".into()),
    };
    let keys = match root.get("keyframes") {
        Some(Json::Array(k)) if !k.is_empty() => k,
        _ => return Err("'keyframes' is missing, not an array, or empty".into()),
    };

    // Every listed name first, so that each keyframe's row has them all.
    let mut names: Vec<String> = Vec::new();
    for (k, key) in keys.iter().enumerate() {
        if !matches!(key, Json::Object(_)) {
            return Err(format!("keyframe {k} is not an object"));
        }
        match key.get("weights") {
            Some(Json::Object(members)) => {
                for (n, _) in members {
                    if !names.contains(n) {
                        names.push(n.clone());
                    }
                }
            }
            _ => return Err(format!("keyframe {k}: 'weights' is missing or not an object of name: weight")),
        }
    }
    if names.is_empty() {
        return Err("no keyframe lists a weight".into());
    }

    let mut times = Vec::with_capacity(keys.len());
    let mut rows: Vec<Vec<f32>> = Vec::with_capacity(keys.len());
    let mut has_jaw = false;
    for (k, key) in keys.iter().enumerate() {
        let t = match number(key.get("time")) {
            Some(t) if t.is_finite() => t,
            _ => return Err(format!("keyframe {k}: 'time' is missing or not a finite number")),
        };
        let mut row = vec![0.0f32; names.len()];
        if let Some(Json::Object(members)) = key.get("weights") {
            for (name, value) in members {
                let v = match value {
                    Json::Number(v) if *v >= 0.0 && *v <= 1.0 => *v,
                    _ => return Err(format!("keyframe {k}: weight '{name}' is not a number in [0, 1]")),
                };
                let slot = names.iter().position(|n| n == name).expect("collected above");
                row[slot] = v as f32; // a repeated name: the last one wins
            }
        }
        if k > 0 && t <= times[k - 1] {
            return Err(format!("keyframe {k}: time {t} is not after keyframe {}'s time {}", k - 1, times[k - 1]));
        }
        if key.get("jaw").is_some() {
            has_jaw = true;
        }
        times.push(t);
        rows.push(row);
    }

    let nk = times.len();
    let span = (times[nk - 1] - times[0]) * fps;
    if span >= MAX_FRAMES {
        return Err(format!("the keyframes span more than {MAX_FRAMES} frames"));
    }
    let frames = (span + 1e-6).floor() as usize + 1;
    let n = names.len();
    let mut weights = vec![0.0f32; frames * n];
    let mut k = 0;
    for f in 0..frames {
        let t = (times[0] + f as f64 / fps).min(times[nk - 1]);
        while k + 1 < nk && times[k + 1] <= t {
            k += 1;
        }
        sample(&times, &rows, k, t, &mut weights[f * n..(f + 1) * n]);
    }
    Ok(Performance { fps, frames, names, weights, has_jaw })
}

/// Weights at time t, with k the keyframe at or before it. Times within
/// rounding of a keyframe take it exactly, as the engine does.
fn sample(times: &[f64], rows: &[Vec<f32>], k: usize, t: f64, out: &mut [f32]) {
    if k + 1 >= times.len() {
        out.copy_from_slice(&rows[k]);
        return;
    }
    let alpha = (t - times[k]) / (times[k + 1] - times[k]);
    if alpha <= 1e-9 {
        out.copy_from_slice(&rows[k]);
    } else if alpha >= 1.0 - 1e-9 {
        out.copy_from_slice(&rows[k + 1]);
    } else {
        for (i, o) in out.iter_mut().enumerate() {
            let (a, b) = (rows[k][i] as f64, rows[k + 1][i] as f64);
            *o = (a + alpha * (b - a)) as f32;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sparse_keyframes_sample_like_the_engine() {
        // 0.2 s at 30 fps: 7 frames; mouthSmile_L is 0 where not listed.
        let text = br#"{"format": "facesr-performance", "version": 1, "fps": 30, "extra": [1, {"x": null}],
            "keyframes": [{"time": 0, "weights": {"jawOpen": 0}},
                          {"time": 0.1, "weights": {"jawOpen": 0.5, "mouthSmile_L": 1e-1}},
                          {"time": 0.2, "weights": {}}]}"#;
        let p = build(&json::parse(text).unwrap()).unwrap();
        assert_eq!(p.frames, 7);
        assert_eq!(p.names, vec!["jawOpen".to_string(), "mouthSmile_L".to_string()]);
        assert_eq!(p.frame(0), &[0.0, 0.0]);
        assert_eq!(p.frame(3), &[0.5, 0.1]);
        assert_eq!(p.frame(6), &[0.0, 0.0]);
        assert!((p.frame(1)[0] - 0.5 / 3.0).abs() < 1e-6);
    }

    #[test]
    fn bad_files_say_why() {
        let bad = |t: &str| build(&json::parse(t.as_bytes()).unwrap()).unwrap_err();
        assert!(bad("[]").contains("not a JSON object"));
        assert!(bad(r#"{"format":"x"}"#).contains("'format'"));
        let head = r#"{"format":"facesr-performance","version":1,"fps":30,"keyframes":"#;
        assert!(bad(&format!("{head}[]}}")).contains("'keyframes'"));
        assert!(bad(&format!(r#"{head}[{{"time":0,"weights":{{"a":1.5}}}}]}}"#)).contains("weight 'a'"));
        assert!(bad(&format!(r#"{head}[{{"time":1,"weights":{{"a":1}}}},{{"time":1,"weights":{{}}}}]}}"#))
            .contains("not after"));
    }
}
