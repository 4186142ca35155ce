// FacesrPlay.exe (facesr_play_cs): plays a performance through the C#
// bindings the way a game loop would (per frame: set weights by name, step,
// read the surface back) and writes the surface of every frame. The C# twin
// of samples/c/play.c, with the same options and the same sampling.
//
//   mono FacesrPlay.exe --rig R.rig --model M.fsm --performance P.json --out frames.bin|frames.obj
//                       [--frames N] [--async] [--inference auto|opencl|cpu] [--device NAME]
using System;
using System.Diagnostics;
using System.IO;
using Facesr;

namespace FacesrSample
{
    sealed class Options
    {
        public string Rig, Model, Performance, Out, Device, Inference = "auto";
        public int MaxFrames = -1;  // -1: the whole performance
        public bool Async;
    }

    static class FacesrPlay
    {
        const string Me = "facesr_play_cs";

        static void Usage(TextWriter w)
        {
            w.WriteLine("usage: FacesrPlay.exe --rig R.rig --model M.fsm --performance P.json --out frames.bin|frames.obj");
            w.WriteLine("                      [--frames N] [--async] [--inference auto|opencl|cpu] [--device NAME]");
            w.WriteLine("  --out          .bin: raw little-endian float32, frames x vertices x 3 (cm); .obj: one object per frame");
            w.WriteLine("  --frames N     play at most the first N frames");
            w.WriteLine("  --async        pipelined stepping (StepAsync + Wait, one frame of latency)");
            w.WriteLine("  --inference    auto (default): OpenCL, else the CPU reference; or force one");
            w.WriteLine("  --device NAME  OpenCL device (substring of device or platform name; default: first CPU)");
        }

        // null on a usage error (already reported).
        static Options Parse(string[] args)
        {
            var o = new Options();
            for (int i = 0; i < args.Length; ++i)
            {
                string a = args[i];
                if (a == "--help" || a == "-h")
                {
                    Usage(Console.Out);
                    Environment.Exit(0);
                }
                if (a == "--async")
                {
                    o.Async = true;
                    continue;
                }
                if (a != "--rig" && a != "--model" && a != "--performance" && a != "--out" && a != "-o" &&
                    a != "--device" && a != "--inference" && a != "--frames")
                {
                    Console.Error.WriteLine(Me + ": unknown option '" + a + "'");
                    Usage(Console.Error);
                    return null;
                }
                if (i + 1 >= args.Length)
                {
                    Console.Error.WriteLine(Me + ": " + a + " needs a value");
                    return null;
                }
                string v = args[++i];
                switch (a)
                {
                    case "--rig": o.Rig = v; break;
                    case "--model": o.Model = v; break;
                    case "--performance": o.Performance = v; break;
                    case "--out": case "-o": o.Out = v; break;
                    case "--device": o.Device = v; break;
                    case "--inference": o.Inference = v; break;
                    case "--frames":
                        int n;
                        if (!int.TryParse(v, System.Globalization.NumberStyles.None,
                                          System.Globalization.CultureInfo.InvariantCulture, out n) ||
                            n < 1 || n > 1000000)
                        {
                            Console.Error.WriteLine(Me + ": --frames wants a positive number, got '" + v + "'");
                            return null;
                        }
                        o.MaxFrames = n;
                        break;
                }
            }
            if (o.Rig == null || o.Model == null || o.Performance == null || o.Out == null)
            {
                Console.Error.WriteLine(Me + ": --rig, --model, --performance and --out are required");
                Usage(Console.Error);
                return null;
            }
            if (o.Inference != "auto" && o.Inference != "opencl" && o.Inference != "cpu")
            {
                Console.Error.WriteLine(Me + ": --inference is auto, opencl or cpu, not '" + o.Inference + "'");
                return null;
            }
            if (!FrameWriter.Supports(o.Out))
            {
                Console.Error.WriteLine(Me + ": --out must end in .bin or .obj, not '" + o.Out + "'");
                return null;
            }
            return o;
        }

        static Context CreateContext(Rig rig, Model model, Options o)
        {
            var opts = new ContextOptions
            {
                DeviceName = o.Device,
                Inference = o.Inference == "cpu" ? Inference.Cpu : Inference.OpenCL,
            };
            try
            {
                return new Context(rig, model, opts);
            }
            catch (FacesrException e) when (e.Status == Status.Device && o.Inference == "auto")
            {
                Console.Error.WriteLine(Me + ": OpenCL inference unavailable (" + e.EngineMessage +
                                        "); using the CPU reference");
                opts.Inference = Inference.Cpu;
                return new Context(rig, model, opts);
            }
        }

        // Frame f's weights by name, as a game forwarding named controls would.
        static void SetFrameWeights(Context c, Performance perf, int f)
        {
            int n = perf.Names.Length;
            for (int i = 0; i < n; ++i) c.SetWeight(perf.Names[i], perf.Weights[f * n + i]);
        }

        // The game loop. Async keeps one frame in flight: tick f submits frame
        // f and shows frame f - 1, so simulation and super-resolution overlap.
        // Frames come back in order, so each is written as it arrives.
        static void Play(Context c, Performance perf, int frames, bool async, FrameWriter writer)
        {
            var xyz = new float[c.PositionFloats];
            double simMs = 0, srMs = 0;
            long expected = 0;
            Action<long> show = frame =>
            {
                if (frame != expected) throw new InvalidOperationException("frame " + frame + " came back, expected " + expected);
                ++expected;
                c.GetPositions(xyz);
                FrameStats st = c.GetFrameStats();
                simMs += st.SimulationMs;
                srMs += st.InferenceMs;
                writer.Write(xyz);
            };
            var watch = Stopwatch.StartNew();
            for (int f = 0; f < frames; ++f)
            {
                SetFrameWeights(c, perf, f);
                if (!async)
                {
                    c.Step();
                    show(f);
                    continue;
                }
                c.StepAsync();
                if (c.PendingFrames > 1) show(c.Wait());
            }
            while (async && c.PendingFrames > 0) show(c.Wait());
            double seconds = watch.Elapsed.TotalSeconds;
            Console.WriteLine(string.Format(System.Globalization.CultureInfo.InvariantCulture,
                "played {0} frames in {1:F2} s: {2:F1} FPS ({3}; mean {4:F2} ms simulation, {5:F2} ms super-resolution per frame)",
                frames, seconds, seconds > 0 ? frames / seconds : 0, async ? "async" : "sync", simMs / frames, srMs / frames));
        }

        static int Main(string[] args)
        {
            Options o = Parse(args);
            if (o == null) return 2;
            try
            {
                Console.WriteLine(FacesrLibrary.VersionString + " (C ABI " + FacesrLibrary.AbiVersion + ")");
                FacesrLibrary.EnsureCompatible();
                using (var rig = Rig.Load(o.Rig))
                using (var model = Model.Load(o.Model))
                {
                    Performance perf = Performance.Load(o.Performance);
                    foreach (string name in perf.Names) rig.BlendshapeIndex(name);  // every name must be the rig's
                    if (perf.HasJaw)
                        Console.Error.WriteLine(Me + ": " + o.Performance + " has explicit jaw transforms; they are " +
                                                "not played (the jaw follows the jaw blendshapes)");
                    int frames = o.MaxFrames > 0 && o.MaxFrames < perf.Frames ? o.MaxFrames : perf.Frames;
                    using (Context c = CreateContext(rig, model, o))
                    {
                        Console.WriteLine("rig: " + rig.BlendshapeCount + " blendshapes, " + rig.VertexCount +
                                          " surface vertices, " + rig.Info.NumLrNodes + " LR nodes; performance: " +
                                          frames + " frames at " + perf.Fps + " fps");
                        using (var writer = new FrameWriter(o.Out, rig.VertexCount, rig.GetTriangles()))
                        {
                            Play(c, perf, frames, o.Async, writer);
                            writer.Commit();
                        }
                    }
                }
                Console.WriteLine("wrote " + o.Out);
                return 0;
            }
            catch (FacesrException e)
            {
                Console.Error.WriteLine(Me + ": " + e.Message);
            }
            catch (InvalidDataException e)
            {
                Console.Error.WriteLine(Me + ": " + e.Message);
            }
            catch (Exception e)  // I/O, a missing native library, ...: a message, never a crash
            {
                Console.Error.WriteLine(Me + ": " + e.GetType().Name + ": " + e.Message);
            }
            return 1;
        }
    }
}
