//! The played surface, frame by frame, to
//!   .bin  raw little-endian f32, frames × vertices × 3 (cm), nothing else:
//!         the format the samples_agree test compares across C, C# and Rust;
//!   .obj  one Wavefront object per frame ("o frame_0000"), each with its own
//!         vertices (cm) and the rig's triangles.
//! Written to OUT.partial and renamed when complete, so a failure never
//! leaves a partial file under the requested name.
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

pub struct FrameWriter {
    path: PathBuf,
    partial: PathBuf,
    out: Option<BufWriter<File>>,
    obj: bool,
    triangles: Vec<i32>,
    vertices: usize,
    frames: usize,
}

fn extension(path: &Path) -> Option<String> {
    path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase())
}

impl FrameWriter {
    pub fn supports(path: &Path) -> bool {
        matches!(extension(path).as_deref(), Some("bin") | Some("obj"))
    }

    pub fn create(path: &Path, vertices: usize, triangles: Vec<i32>) -> std::io::Result<FrameWriter> {
        let mut partial = path.as_os_str().to_owned();
        partial.push(".partial");
        let partial = PathBuf::from(partial);
        let obj = extension(path).as_deref() == Some("obj");
        let mut out = BufWriter::new(File::create(&partial)?);
        if obj {
            writeln!(out, "# facesr_play_rs: one object per frame, positions in cm")?;
        }
        Ok(FrameWriter { path: path.to_owned(), partial, out: Some(out), obj, triangles, vertices, frames: 0 })
    }

    pub fn write(&mut self, xyz: &[f32]) -> std::io::Result<()> {
        let out = self.out.as_mut().expect("not committed yet");
        if self.obj {
            writeln!(out, "o frame_{:04}", self.frames)?;
            for v in xyz.chunks(3) {
                // `{:?}` prints the shortest text that reads back as the same f32.
                writeln!(out, "v {:?} {:?} {:?}", v[0], v[1], v[2])?;
            }
            let first = self.frames * self.vertices + 1; // OBJ indices are 1-based and global
            for t in self.triangles.chunks(3) {
                writeln!(out, "f {} {} {}", first + t[0] as usize, first + t[1] as usize, first + t[2] as usize)?;
            }
        } else {
            for v in xyz {
                out.write_all(&v.to_le_bytes())?;
            }
        }
        self.frames += 1;
        Ok(())
    }

    /// Flushes and renames the file into place.
    pub fn commit(mut self) -> std::io::Result<()> {
        let out = self.out.take().expect("committed once");
        let file = out.into_inner().map_err(|e| e.into_error())?;
        file.sync_all()?;
        drop(file);
        std::fs::rename(&self.partial, &self.path)
    }
}

impl Drop for FrameWriter {
    /// Without commit: the partial file is removed.
    fn drop(&mut self) {
        if self.out.take().is_some() {
            let _ = std::fs::remove_file(&self.partial);
        }
    }
}
