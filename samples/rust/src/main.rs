//! facesr_play_rs: plays a performance through the safe `facesr` crate the
//! way a game loop would (per frame: set weights by name, step, read the
//! surface back) and writes the surface of every frame. The Rust twin of
//! samples/c/play.c, with the same options and the same sampling.
//!
//!   facesr_play_rs --rig R.rig --model M.fsm --performance P.json --out frames.bin|frames.obj
//!                  [--frames N] [--async] [--inference auto|opencl|cpu] [--device NAME]
mod frame_writer;
mod json;
mod performance;

use facesr::{Context, ContextOptions, Inference, Model, Rig, Status};
use frame_writer::FrameWriter;
use performance::Performance;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::Arc;
use std::time::Instant;

const ME: &str = "facesr_play_rs";

const USAGE: &str = "\
usage: facesr_play_rs --rig R.rig --model M.fsm --performance P.json --out frames.bin|frames.obj
                      [--frames N] [--async] [--inference auto|opencl|cpu] [--device NAME]
  --out          .bin: raw little-endian float32, frames x vertices x 3 (cm); .obj: one object per frame
  --frames N     play at most the first N frames
  --async        pipelined stepping (step_async + wait, one frame of latency)
  --inference    auto (default): OpenCL, else the CPU reference; or force one
  --device NAME  OpenCL device (substring of device or platform name; default: first CPU)";

struct Options {
    rig: PathBuf,
    model: PathBuf,
    performance: PathBuf,
    out: PathBuf,
    device: Option<String>,
    inference: String,
    max_frames: Option<usize>,
    pipelined: bool,
}

/// Err: a usage error, already explained.
fn parse_args(args: &[String]) -> Result<Options, String> {
    let (mut rig, mut model, mut perf, mut out) = (None, None, None, None);
    let mut o = Options {
        rig: PathBuf::new(),
        model: PathBuf::new(),
        performance: PathBuf::new(),
        out: PathBuf::new(),
        device: None,
        inference: "auto".into(),
        max_frames: None,
        pipelined: false,
    };
    let mut it = args.iter();
    while let Some(a) = it.next() {
        match a.as_str() {
            "--help" | "-h" => {
                println!("{USAGE}");
                std::process::exit(0);
            }
            "--async" => {
                o.pipelined = true;
                continue;
            }
            "--rig" | "--model" | "--performance" | "--out" | "-o" | "--device" | "--inference" | "--frames" => {}
            _ => return Err(format!("unknown option '{a}'\n{USAGE}")),
        }
        let v = it.next().ok_or_else(|| format!("{a} needs a value"))?.clone();
        match a.as_str() {
            "--rig" => rig = Some(PathBuf::from(v)),
            "--model" => model = Some(PathBuf::from(v)),
            "--performance" => perf = Some(PathBuf::from(v)),
            "--out" | "-o" => out = Some(PathBuf::from(v)),
            "--device" => o.device = Some(v),
            "--inference" => o.inference = v,
            _ => match v.parse::<usize>() {
                Ok(n) if (1..=1_000_000).contains(&n) && v.bytes().all(|b| b.is_ascii_digit()) => {
                    o.max_frames = Some(n)
                }
                _ => return Err(format!("--frames wants a positive number, got '{v}'")),
            },
        }
    }
    match (rig, model, perf, out) {
        (Some(r), Some(m), Some(p), Some(w)) => {
            o.rig = r;
            o.model = m;
            o.performance = p;
            o.out = w;
        }
        _ => return Err(format!("--rig, --model, --performance and --out are required\n{USAGE}")),
    }
    if !["auto", "opencl", "cpu"].contains(&o.inference.as_str()) {
        return Err(format!("--inference is auto, opencl or cpu, not '{}'", o.inference));
    }
    if !FrameWriter::supports(&o.out) {
        return Err(format!("--out must end in .bin or .obj, not '{}'", o.out.display()));
    }
    Ok(o)
}

fn create_context(rig: &Arc<Rig>, model: &Arc<Model>, o: &Options) -> facesr::Result<Context> {
    let mut opts = ContextOptions {
        device_name: o.device.clone(),
        inference: if o.inference == "cpu" { Inference::Cpu } else { Inference::OpenCl },
        ..ContextOptions::default()
    };
    match Context::new(rig.clone(), model.clone(), &opts) {
        Err(e) if e.status() == Status::Device && o.inference == "auto" => {
            eprintln!("{ME}: OpenCL inference unavailable ({}); using the CPU reference", e.message());
            opts.inference = Inference::Cpu;
            Context::new(rig.clone(), model.clone(), &opts)
        }
        r => r,
    }
}

/// Totals over the played frames, for the closing line.
#[derive(Default)]
struct Totals {
    simulation_ms: f64,
    inference_ms: f64,
    next_frame: i64,
}

/// Reads the readable frame back and writes it; frames must arrive in order.
fn show(c: &Context, frame: i64, xyz: &mut [f32], totals: &mut Totals, out: &mut FrameWriter) -> Result<(), String> {
    if frame != totals.next_frame {
        return Err(format!("frame {frame} came back, expected {}", totals.next_frame));
    }
    totals.next_frame += 1;
    c.get_positions(xyz).map_err(|e| e.to_string())?;
    let st = c.frame_stats().map_err(|e| e.to_string())?;
    totals.simulation_ms += st.simulation_ms as f64;
    totals.inference_ms += st.inference_ms as f64;
    out.write(xyz).map_err(|e| format!("writing the output: {e}"))
}

/// The game loop. Async keeps one frame in flight: tick f submits frame f and
/// shows frame f - 1, so simulation and super-resolution overlap.
fn play(
    c: &mut Context,
    perf: &Performance,
    frames: usize,
    pipelined: bool,
    out: &mut FrameWriter,
) -> Result<(), String> {
    let mut xyz = vec![0.0f32; c.position_len()];
    let mut totals = Totals::default();
    let start = Instant::now();
    let fail = |e: facesr::Error| e.to_string();
    for f in 0..frames {
        // By name, as a game forwarding named controls would.
        for (name, &w) in perf.names.iter().zip(perf.frame(f)) {
            c.set_weight_by_name(name, w).map_err(fail)?;
        }
        if !pipelined {
            c.step().map_err(fail)?;
            show(c, f as i64, &mut xyz, &mut totals, out)?;
            continue;
        }
        c.step_async().map_err(fail)?;
        if c.pending_frames().map_err(fail)? > 1 {
            let done = c.wait().map_err(fail)?;
            show(c, done, &mut xyz, &mut totals, out)?;
        }
    }
    while pipelined && c.pending_frames().map_err(fail)? > 0 {
        let done = c.wait().map_err(fail)?;
        show(c, done, &mut xyz, &mut totals, out)?;
    }
    let seconds = start.elapsed().as_secs_f64();
    println!(
        "played {frames} frames in {seconds:.2} s: {:.1} FPS ({}; mean {:.2} ms simulation, {:.2} ms super-resolution per frame)",
        if seconds > 0.0 { frames as f64 / seconds } else { 0.0 },
        if pipelined { "async" } else { "sync" },
        totals.simulation_ms / frames as f64,
        totals.inference_ms / frames as f64
    );
    Ok(())
}

fn run(o: &Options) -> Result<(), String> {
    println!("{} (C ABI {})", facesr::version_string(), facesr::abi_version());
    facesr::ensure_compatible().map_err(|e| e.to_string())?;
    let rig = Arc::new(Rig::load(&o.rig).map_err(|e| e.to_string())?);
    let model = Arc::new(Model::load(&o.model).map_err(|e| e.to_string())?);
    let perf = Performance::load(&o.performance)?;
    for name in &perf.names {
        rig.blendshape_index(name).map_err(|e| format!("{}: {}", o.performance.display(), e.message()))?;
    }
    if perf.has_jaw {
        eprintln!(
            "{ME}: {} has explicit jaw transforms; they are not played (the jaw follows the jaw blendshapes)",
            o.performance.display()
        );
    }
    let frames = o.max_frames.map_or(perf.frames, |n| n.min(perf.frames));
    let mut c = create_context(&rig, &model, o).map_err(|e| e.to_string())?;
    println!(
        "rig: {} blendshapes, {} surface vertices, {} LR nodes; performance: {frames} frames at {} fps",
        rig.num_blendshapes(),
        rig.num_vertices(),
        rig.info().num_lr_nodes,
        perf.fps
    );
    let triangles = rig.triangles().map_err(|e| e.to_string())?;
    let mut out = FrameWriter::create(&o.out, rig.num_vertices(), triangles)
        .map_err(|e| format!("cannot create {}.partial: {e}", o.out.display()))?;
    play(&mut c, &perf, frames, o.pipelined, &mut out)?;
    out.commit().map_err(|e| format!("cannot finish {}: {e}", o.out.display()))?;
    println!("wrote {}", o.out.display());
    Ok(())
}

fn main() -> ExitCode {
    // args_os: std::env::args would panic on an argument that is not Unicode.
    let mut args = Vec::new();
    for a in std::env::args_os().skip(1) {
        match a.into_string() {
            Ok(s) => args.push(s),
            Err(a) => {
                eprintln!("{ME}: argument {} is not valid Unicode", a.to_string_lossy());
                return ExitCode::from(2);
            }
        }
    }
    let o = match parse_args(&args) {
        Ok(o) => o,
        Err(e) => {
            eprintln!("{ME}: {e}");
            return ExitCode::from(2);
        }
    };
    match run(&o) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("{ME}: {e}");
            ExitCode::FAILURE
        }
    }
}
