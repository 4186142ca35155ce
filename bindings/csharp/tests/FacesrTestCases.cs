// The test cases of FacesrTests.exe: the same ground as the Rust tests
// (bindings/rust/facesr/tests/api.rs), plus what only C# can get wrong:
// null and disposed handles, offsets into managed arrays, allocations.
using System;
using System.IO;
using System.Runtime.InteropServices;
using System.Threading;
using Facesr;

static partial class FacesrTests
{
    static void LibraryAndStatusNames()
    {
        FacesrLibrary.EnsureCompatible();
        Check(FacesrLibrary.AbiVersion == Native.FACESR_ABI_VERSION, "ABI version");
        Check(FacesrLibrary.VersionString.StartsWith("facesr "), "version string " + FacesrLibrary.VersionString);
        Check(FacesrException.StatusName(Status.BufferSize) == "FACESR_ERROR_BUFFER_SIZE", "status name");
        Check(FacesrException.StatusName((Status)99) == "unknown", "unknown status name");
        foreach (Status s in Enum.GetValues(typeof(Status)))
            Check(FacesrException.StatusName(s).StartsWith(s == Status.Ok ? "FACESR_OK" : "FACESR_ERROR_"),
                  "name of " + s);
        Check(Utf8.Decode(Native.facesr_last_error_message()) != null, "last error message readable");
    }

    static void LoadErrors()
    {
        string missing = Path.Combine(dataDir, "missing.rig");
        ExpectStatus(Status.File, missing, () => Rig.Load(missing));
        ExpectStatus(Status.File, "facesr_rig_load", () => Rig.Load(modelPath));    // a model is not a rig
        ExpectStatus(Status.File, "facesr_model_load", () => Model.Load(rigPath));  // nor a rig a model
        ExpectStatus(Status.File, "directory", () => Rig.Load(dataDir));
        ExpectThrows<ArgumentNullException>(() => Rig.Load(null));
        ExpectThrows<ArgumentException>(() => Model.Load("a\0b.fsm"));
    }

    static void RigAndModel()
    {
        using (var rig = Rig.Load(rigPath))
        using (var model = Model.Load(modelPath))
        {
            RigInfo info = rig.Info;
            Check(info.StructSize == Marshal.SizeOf(typeof(RigInfo)), "struct_size");
            Check(info.NumBlendshapes > 0 && info.NumSurfaceVertices > 0 && info.NumSurfaceTriangles > 0, "counts");
            Check(info.NumLrNodes > 0 && info.NumMuscles > 0, "lattice and muscles");
            Float3 a = info.JawAxis;
            Check(Math.Abs(Math.Sqrt(a.X * a.X + a.Y * a.Y + a.Z * a.Z) - 1) < 1e-4, "unit jaw axis " + a);
            Check(model.RigChecksum == rig.Checksum, "the model fits the rig");
            Check(model.Info.NumLrNodes == info.NumLrNodes && model.Info.NumSurfaceVertices == info.NumSurfaceVertices,
                  "model sizes");
            Check(model.Info.NumParameters > 0, "parameters");

            string[] names = rig.BlendshapeNames();
            Check(names.Length == info.NumBlendshapes, "one name per blendshape");
            for (int i = 0; i < names.Length; ++i)
            {
                Check(rig.BlendshapeIndex(names[i]) == i, "index of " + names[i]);
                Check(rig.BlendshapeName(i) == names[i], "name " + i);
                int j;
                Check(rig.TryGetBlendshapeIndex(names[i], out j) && j == i, "TryGet " + names[i]);
            }
            Check(Array.IndexOf(names, "jawOpen") >= 0, "an ARKit rig has jawOpen");
            ExpectStatus(Status.NotFound, "jawopen", () => rig.BlendshapeIndex("jawopen"));  // case-sensitive
            int none;
            Check(!rig.TryGetBlendshapeIndex("jawopen", out none) && none == -1, "TryGet of an unknown name");
            ExpectThrows<ArgumentOutOfRangeException>(() => rig.BlendshapeName(names.Length));
        }
    }

    static void GeometryAndBufferSizes()
    {
        using (var rig = Rig.Load(rigPath))
        {
            int[] tris = rig.GetTriangles();
            Check(tris.Length == 3 * rig.TriangleCount, "triangle count");
            foreach (int t in tris) Check(t >= 0 && t < rig.VertexCount, "index in range");
            float[] rest = rig.GetRestPositions();
            Check(rest.Length == rig.PositionFloats && AllFinite(rest), "rest positions");
            ExpectStatus(Status.BufferSize, tris.Length.ToString(), () => rig.GetTriangles(new int[tris.Length - 1]));
            ExpectStatus(Status.BufferSize, rest.Length.ToString(), () => rig.GetRestPositions(new float[rest.Length + 3]));
            ExpectStatus(Status.BufferSize, "xyz", () => rig.GetRestPositions(new float[0]));
            ExpectThrows<ArgumentNullException>(() => rig.GetRestPositions(null));
        }
    }

    static void ContextCreationErrors()
    {
        using (var rig = Rig.Load(rigPath))
        using (var other = Rig.Load(otherRigPath))
        using (var model = Model.Load(modelPath))
        {
            Check(other.Checksum != rig.Checksum, "the other rig differs");
            ExpectStatus(Status.Mismatch, "facesr_context_create", () => NewContext(other, model));
            var opts = new ContextOptions { Inference = Inference.Cpu, DeviceName = "no-such-opencl-device" };
            ExpectStatus(Status.Device, "facesr_context_create", () => new Context(rig, model, opts));
            opts = new ContextOptions { Inference = Inference.Cpu, Solver = (Solver)7 };
            ExpectStatus(Status.InvalidArgument, "solver", () => new Context(rig, model, opts));
            ExpectThrows<ArgumentNullException>(() => new Context(null, model));
            ExpectThrows<ArgumentNullException>(() => new Context(rig, null));
            // Still usable after the failures.
            using (var c = NewContext(rig, model)) c.Step();
        }
    }

    static void WeightsStepAndReadBack()
    {
        using (var rig = Rig.Load(rigPath))
        using (var model = Model.Load(modelPath))
        using (var c = NewContext(rig, model))
        {
            int n = c.PositionFloats;
            var rest = new float[n];
            var pos = new float[n];
            c.GetPositions(rest);
            Check(MaxAbsDiff(rest, rig.GetRestPositions()) == 0, "before the first step: the rest pose");
            Check(c.GetFrameStats().Frame == -1, "no frame yet");

            // Bad controls fail and change nothing.
            ExpectStatus(Status.InvalidArgument, "facesr_set_weight", () => c.SetWeight(0, float.NaN));
            ExpectStatus(Status.InvalidArgument, "facesr_set_weight", () => c.SetWeight(0, 1.5f));
            ExpectStatus(Status.InvalidArgument, "facesr_set_weight", () => c.SetWeight(-1, 0.5f));
            ExpectStatus(Status.InvalidArgument, "facesr_set_weight_by_name", () => c.SetWeight("jawOpen", float.NaN));
            ExpectStatus(Status.NotFound, "jawopen_typo", () => c.SetWeight("jawopen_typo", 0.5f));
            ExpectThrows<ArgumentException>(() => c.SetWeight("jaw\0Open", 0.5f));
            ExpectThrows<ArgumentNullException>(() => c.SetWeight(null, 0.5f));
            var w = new float[rig.BlendshapeCount];
            ExpectStatus(Status.BufferSize, w.Length.ToString(), () => c.SetWeights(new float[w.Length - 1]));
            w[1] = float.NaN;
            ExpectStatus(Status.InvalidArgument, "facesr_set_weights", () => c.SetWeights(w));
            ExpectStatus(Status.BufferSize, n.ToString(), () => c.GetPositions(new float[n - 3]));
            ExpectStatus(Status.BufferSize, n.ToString(), () => c.GetNormals(new float[0]));
            ExpectStatus(Status.BufferSize, n.ToString(), () => c.GetEmbeddedPositions(new float[n + 1]));
            ExpectStatus(Status.State, "facesr_wait", () => c.Wait());
            c.GetPositions(pos);
            Check(MaxAbsDiff(pos, rest) == 0, "failed calls changed nothing");

            c.SetWeight("jawOpen", 0.8f);
            c.Step();
            c.GetPositions(pos);
            Check(AllFinite(pos), "finite positions");
            Check(MaxAbsDiff(pos, rest) > 0.01f, "the mouth opened (cm)");
            FrameStats st = c.GetFrameStats();
            Check(st.Frame == 0 && st.NewtonIterations > 0 && st.TotalMs > 0, "frame stats");
            var normals = new float[n];
            c.GetNormals(normals);
            for (int v = 0; v < n; v += 3)
            {
                double len = Math.Sqrt(normals[v] * normals[v] + normals[v + 1] * normals[v + 1] +
                                       normals[v + 2] * normals[v + 2]);
                Check(Math.Abs(len - 1) < 1e-3, "unit normal at " + v / 3 + ": " + len);
            }
            var embedded = new float[n];
            c.GetEmbeddedPositions(embedded);
            Check(MaxAbsDiff(embedded, rest) > 0.01f, "the embedded surface moved too");

            // The same weights by index give the same surface.
            using (var d = NewContext(rig, model))
            {
                d.SetWeight(rig.BlendshapeIndex("jawOpen"), 0.8f);
                d.Step();
                var same = new float[n];
                d.GetPositions(same);
                Check(MaxAbsDiff(same, pos) == 0, "by index == by name");
            }

            c.Reset();
            c.GetPositions(pos);
            Check(MaxAbsDiff(pos, rest) == 0, "reset returns the rest pose");
        }
    }

    static void OffsetsIntoLargerArrays()
    {
        using (var rig = Rig.Load(rigPath))
        using (var model = Model.Load(modelPath))
        using (var c = NewContext(rig, model))
        {
            int n = c.PositionFloats, nb = rig.BlendshapeCount;
            int jaw = rig.BlendshapeIndex("jawOpen");
            // A frames x blendshapes table and a frames x 3M one, filled in place.
            var table = new float[2 * nb];
            table[nb + jaw] = 0.6f;
            var frames = new float[2 * n + 5];
            for (int f = 0; f < 2; ++f)
            {
                c.SetWeights(table, f * nb);
                c.Step();
                c.GetPositions(frames, 5 + f * n);
            }
            var last = new float[n];
            c.GetPositions(last);
            for (int i = 0; i < n; ++i) Check(frames[5 + n + i] == last[i], "frame 1 written at its offset");
            Check(frames[0] == 0 && frames[4] == 0, "nothing written before the offset");
            ExpectThrows<ArgumentOutOfRangeException>(() => c.GetPositions(frames, n + 6));  // runs past the end
            ExpectThrows<ArgumentOutOfRangeException>(() => c.GetPositions(frames, -1));
            ExpectThrows<ArgumentOutOfRangeException>(() => c.SetWeights(table, nb + 1));
            ExpectThrows<ArgumentOutOfRangeException>(() => c.GetNormals(new float[n - 1], 0));

            // Caller-pinned memory (a Unity NativeArray or pinned Vector3[]).
            var pinned = new float[n];
            GCHandle h = GCHandle.Alloc(pinned, GCHandleType.Pinned);
            try
            {
                c.GetPositions(h.AddrOfPinnedObject(), n);
                ExpectStatus(Status.BufferSize, n.ToString(), () => c.GetPositions(h.AddrOfPinnedObject(), n - 1));
                ExpectStatus(Status.NullArgument, "xyz", () => c.GetPositions(IntPtr.Zero, n));
            }
            finally
            {
                h.Free();
            }
            Check(MaxAbsDiff(pinned, last) == 0, "IntPtr read-back");
        }
    }

    static void AsyncEqualsSync()
    {
        using (var rig = Rig.Load(rigPath))
        using (var model = Model.Load(modelPath))
        using (var sync = NewContext(rig, model))
        using (var pipe = NewContext(rig, model))
        {
            int n = sync.PositionFloats;
            float[] weights = { 0.3f, 0.7f, 0.1f };
            var want = new float[weights.Length][];
            var got = new float[weights.Length][];
            for (int f = 0; f < weights.Length; ++f)
            {
                sync.SetWeight("jawOpen", weights[f]);
                sync.Step();
                want[f] = new float[n];
                sync.GetPositions(want[f]);
            }
            for (int i = 0; i < weights.Length; ++i)
            {
                pipe.SetWeight("jawOpen", weights[i]);
                pipe.StepAsync();
                // Two frames in flight, one shown; the last tick leaves two.
                if (pipe.PendingFrames == 2 && i + 1 < weights.Length)
                {
                    long f = pipe.Wait();
                    got[f] = new float[n];
                    pipe.GetPositions(got[f]);
                }
            }
            Check(pipe.PendingFrames == 2, "two frames in flight");
            ExpectStatus(Status.State, "facesr_step_async", () => pipe.StepAsync());
            ExpectStatus(Status.State, "facesr_step", () => pipe.Step());
            while (pipe.PendingFrames > 0)
            {
                long f = pipe.Wait();
                got[f] = new float[n];
                pipe.GetPositions(got[f]);
            }
            ExpectStatus(Status.State, "facesr_wait", () => pipe.Wait());
            Check(pipe.GetFrameStats().Frame == 2, "the last frame is readable");
            for (int f = 0; f < weights.Length; ++f)
                Check(MaxAbsDiff(got[f], want[f]) == 0, "async frame " + f + " == sync frame");
            // Disposing with frames in flight waits for them.
            pipe.StepAsync();
        }
    }

    // The soft-tissue vertex that jawOpen moves most (on the LR embedding).
    static int JawVertex(Context c, float[] rest)
    {
        c.SetWeight("jawOpen", 1);
        c.Step();
        var open = new float[rest.Length];
        c.GetEmbeddedPositions(open);
        c.Reset();
        int best = 0;
        double most = -1;
        for (int i = 0; i < rest.Length / 3; ++i)
        {
            double d = 0;
            for (int k = 0; k < 3; ++k) d += Math.Pow(open[3 * i + k] - rest[3 * i + k], 2);
            if (d > most)
            {
                most = d;
                best = i;
            }
        }
        return best;
    }

    static void SpringsAndSpheres()
    {
        using (var rig = Rig.Load(rigPath))
        using (var model = Model.Load(modelPath))
        using (var c = NewContext(rig, model))
        {
            int n = c.PositionFloats;
            var rest = new float[n];
            c.GetPositions(rest);
            int v = JawVertex(c, rest);
            var at = new Float3(rest[3 * v], rest[3 * v + 1], rest[3 * v + 2]);
            var forward = new Float3(at.X, at.Y, at.Z + 1);  // 1 cm out of the face

            SpringDef def = SpringDef.Default;
            Check(def.StructSize == Marshal.SizeOf(typeof(SpringDef)) && def.Vertex == -1 && def.Stiffness == 100,
                  "spring defaults");
            ExpectStatus(Status.InvalidArgument, "facesr_add_spring", () => c.AddSpring(def));  // vertex -1
            ExpectStatus(Status.InvalidArgument, "", () => c.AddSpring(rig.VertexCount, forward, 100));
            ExpectStatus(Status.InvalidArgument, "", () => c.AddSpring(v, forward, 0));
            ExpectStatus(Status.InvalidArgument, "", () => c.AddSpring(v, new Float3(0, float.NaN, 0), 100));
            var raw = new SpringDef { Vertex = v, Target = forward, Stiffness = 100 };  // struct_size 0
            ExpectStatus(Status.InvalidArgument, "struct_size", () => c.AddSpring(raw));
            ExpectStatus(Status.InvalidArgument, "12345", () => c.MoveSpring(12345, forward));

            int id = c.AddSpring(v, forward, 100);
            Check(id > 0, "positive id");
            c.Step();
            var pulled = new float[n];
            c.GetEmbeddedPositions(pulled);
            Check(pulled[3 * v + 2] - at.Z > 0.05f, "vertex " + v + " pulled forward: " + at.Z + " -> " + pulled[3 * v + 2]);
            c.MoveSpring(id, at);
            ExpectStatus(Status.InvalidArgument, "", () => c.MoveSpring(id, new Float3(0, float.NaN, 0)));
            ExpectStatus(Status.InvalidArgument, "", () => c.RemoveSphere(id));  // a spring's id is no sphere's
            c.RemoveSpring(id);
            ExpectStatus(Status.InvalidArgument, id.ToString(), () => c.RemoveSpring(id));

            SphereDef sd = SphereDef.Default;
            Check(sd.Radius == 1 && sd.Stiffness == 200, "sphere defaults");
            ExpectStatus(Status.InvalidArgument, "", () => c.AddSphere(at, 0, 200));
            ExpectStatus(Status.InvalidArgument, "", () => c.AddSphere(at, 1, -5));
            int s = c.AddSphere(at, 1, 200);
            Check(s > id, "ids are never reused");
            c.Step();
            c.GetPositions(pulled);
            Check(AllFinite(pulled), "finite with a sphere");
            c.MoveSphere(s, new Float3(1e3f, 1e3f, 1e3f));
            ExpectStatus(Status.InvalidArgument, "", () => c.MoveSphere(s + 1, at));
            c.RemoveSphere(s);
            ExpectStatus(Status.InvalidArgument, "", () => c.RemoveSphere(s));
        }
    }

    static void JawTransform()
    {
        using (var rig = Rig.Load(rigPath))
        using (var model = Model.Load(modelPath))
        using (var c = NewContext(rig, model))
        {
            var rest = new float[c.PositionFloats];
            c.GetPositions(rest);
            float[] scaled = { 2, 0, 0, 0, 1, 0, 0, 0, 1 };
            ExpectStatus(Status.InvalidArgument, "facesr_set_jaw_transform",
                         () => c.SetJawTransform(scaled, new Float3(0, 0, 0)));
            ExpectThrows<ArgumentException>(() => c.SetJawTransform(new float[8], new Float3(0, 0, 0)));
            float[] identity = { 1, 0, 0, 0, 1, 0, 0, 0, 1 };
            c.SetJawTransform(identity, new Float3(0, -0.3f, 0));
            c.Step();
            var pos = new float[rest.Length];
            c.GetPositions(pos);
            Check(MaxAbsDiff(pos, rest) > 0.01f, "the jaw moved down");
            c.ClearJawTransform();
        }
    }

    // A frame the simulation cannot solve (the jaw thrown 3 m away) says so
    // and returns the last good surface; the next sane frame plays again.
    static void DivergedFrameKeepsTheLastGoodSurface()
    {
        using (var rig = Rig.Load(rigPath))
        using (var model = Model.Load(modelPath))
        using (var c = NewContext(rig, model))
        {
            c.SetWeight("jawOpen", 0.3f);
            c.Step();
            FrameStats st = c.GetFrameStats();
            Check(st.Status == FrameStatus.Converged || st.Status == FrameStatus.Unconverged, "a sane frame: " + st.Status);
            Check(st.Recoveries == 0, "no recovery needed");
            var good = new float[c.PositionFloats];
            c.GetPositions(good);
            float[] identity = { 1, 0, 0, 0, 1, 0, 0, 0, 1 };
            c.SetJawTransform(identity, new Float3(0, -300, 0));
            c.Step();
            st = c.GetFrameStats();
            Check(st.Status == FrameStatus.Diverged, "the thrown jaw diverges: " + st.Status);
            Check(st.Recoveries > 0, "recovery was tried");
            var pos = new float[good.Length];
            c.GetPositions(pos);
            Check(AllFinite(pos) && MaxAbsDiff(pos, good) == 0, "the last good surface is returned");
            c.ClearJawTransform();
            c.Step();
            Check(c.GetFrameStats().Status != FrameStatus.Diverged, "the next sane frame plays");
            c.SetWeight("jawOpen", 1.05f);  // a capture overshoot: clamped
            ExpectStatus(Status.InvalidArgument, "1.1", () => c.SetWeight("jawOpen", 1.2f));
        }
    }

    static void NullAndDisposedHandles()
    {
        // NULL handles reach the library, which names them.
        ExpectStatus(Status.NullArgument, "context", () => FacesrException_Check(Native.facesr_step(new ContextHandle())));
        ExpectStatus(Status.NullArgument, "rig",
                     () => FacesrException_Check(Native.facesr_rig_get_triangles(new RigHandle(), new int[3], 3)));
        ExpectStatus(Status.NullArgument, "path", () =>
        {
            RigHandle h;
            FacesrException_Check(Native.facesr_rig_load(null, out h));
        });

        var rig = Rig.Load(rigPath);
        var model = Model.Load(modelPath);
        var c = NewContext(rig, model);
        ContextHandle raw = c.Handle;
        c.Dispose();
        c.Dispose();  // twice is harmless
        ExpectThrows<ObjectDisposedException>(() => c.Step());
        ExpectThrows<ObjectDisposedException>(() => c.GetPositions(new float[c.PositionFloats]));
        ExpectThrows<ObjectDisposedException>(() => c.SetWeight("jawOpen", 0.5f));
        rig.Dispose();
        ExpectThrows<ObjectDisposedException>(() => rig.GetTriangles());
        ExpectThrows<ObjectDisposedException>(() => NewContext(rig, model));
        Check(rig.VertexCount > 0, "the cached info outlives the handle");
        // The marshaller refuses a closed handle too, without calling the library.
        ExpectThrows<ObjectDisposedException>(() => Native.facesr_context_reset(raw));
        model.Dispose();
    }

    // Native.* returns a status; the safe layer's check, for the raw calls above.
    static void FacesrException_Check(int status)
    {
        if (status != Native.FACESR_OK)
            throw new FacesrException((Status)status, Utf8.Decode(Native.facesr_last_error_message()));
    }

    static void ContextKeepsRigAndModelAlive()
    {
        var rig = Rig.Load(rigPath);
        var model = Model.Load(modelPath);
        using (var c = NewContext(rig, model))
        {
            rig.Dispose();
            model.Dispose();
            GC.Collect();
            GC.WaitForPendingFinalizers();
            c.SetWeight("jawOpen", 0.5f);
            c.Step();
            var pos = new float[c.PositionFloats];
            c.GetPositions(pos);
            Check(AllFinite(pos), "stepping after the rig and model handles were disposed");
        }
        // Contexts dropped without Dispose are freed by their finalizers,
        // before their rig and model.
        for (int i = 0; i < 2; ++i)
        {
            var r = Rig.Load(rigPath);
            var m = Model.Load(modelPath);
            NewContext(r, m).Step();
        }
        GC.Collect();
        GC.WaitForPendingFinalizers();
    }

    static void ContextsOnTwoThreads()
    {
        using (var rig = Rig.Load(rigPath))
        using (var model = Model.Load(modelPath))
        {
            float[] weights = { 0.2f, 0.6f };
            var results = new float[2][];
            var errors = new Exception[2];
            var threads = new Thread[2];
            for (int t = 0; t < 2; ++t)
            {
                int k = t;
                threads[t] = new Thread(() =>
                {
                    try
                    {
                        using (var c = NewContext(rig, model))
                        {
                            c.SetWeight("jawOpen", weights[k]);
                            c.Step();
                            results[k] = new float[c.PositionFloats];
                            c.GetPositions(results[k]);
                            // The error message is per thread.
                            try
                            {
                                c.SetWeight("noSuchShape" + k, 0);
                            }
                            catch (FacesrException e)
                            {
                                if (!e.EngineMessage.Contains("noSuchShape" + k)) throw;
                            }
                        }
                    }
                    catch (Exception e)
                    {
                        errors[k] = e;
                    }
                });
                threads[t].Start();
            }
            foreach (var th in threads) th.Join();
            foreach (var e in errors)
                if (e != null) throw e;
            Check(MaxAbsDiff(results[0], results[1]) > 0, "different weights, different faces");
        }
    }

    static void HotPathDoesNotAllocate()
    {
        var counter = typeof(GC).GetMethod("GetAllocatedBytesForCurrentThread");
        if (counter == null)
        {
            Console.WriteLine("  (GC.GetAllocatedBytesForCurrentThread missing: allocation check skipped)");
            return;
        }
        var allocated = (Func<long>)Delegate.CreateDelegate(typeof(Func<long>), counter);
        using (var rig = Rig.Load(rigPath))
        using (var model = Model.Load(modelPath))
        using (var c = NewContext(rig, model))
        {
            var pos = new float[c.PositionFloats];
            var normals = new float[c.PositionFloats];
            var table = new float[2 * rig.BlendshapeCount];
            // Warm up: JIT compilation and first-call marshalling stubs allocate.
            for (int i = 0; i < 2; ++i) Frame(c, table, pos, normals, i);
            long before = allocated();
            for (int i = 0; i < 3; ++i) Frame(c, table, pos, normals, i);
            long after = allocated();
            Check(after - before == 0, (after - before) + " bytes allocated in 3 frames");
        }
    }

    // One game tick: weights by name and from a table, sync and async steps,
    // read-back and stats.
    static void Frame(Context c, float[] table, float[] pos, float[] normals, int i)
    {
        c.SetWeights(table, (i % 2) * c.Rig.BlendshapeCount);
        c.SetWeight("jawOpen", 0.1f * i);
        c.Step();
        c.GetPositions(pos);
        c.GetNormals(normals, 0);
        c.StepAsync();
        c.Wait();
        c.GetPositions(pos, 0);
        FrameStats st = c.GetFrameStats();
        if (st.Frame < 0) throw new CheckFailed("frame stats");
    }
}
