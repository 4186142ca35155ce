// FacesrTests.exe: the C# bindings against libfacesr on the tiny procedural
// rig (ctest csharp_bindings). No test framework: each test is a method, run
// in turn; a failed check throws, the runner reports it and goes on.
//   mono FacesrTests.exe DATA_DIR OTHER_RIG
// DATA_DIR holds p.rig, p.fsm (fixture capi_test_data); OTHER_RIG is a rig
// the model was not trained on (fixture bindings_test_data).
using System;
using System.Collections.Generic;
using System.IO;
using System.Threading;
using Facesr;

static partial class FacesrTests
{
    static string rigPath, modelPath, otherRigPath, dataDir;

    // -------------------------------------------------------- checks

    class CheckFailed : Exception
    {
        public CheckFailed(string m) : base(m) { }
    }

    static void Check(bool ok, string what)
    {
        if (!ok) throw new CheckFailed(what);
    }

    // `action` throws FacesrException with `status` and a message containing
    // `needle` (the engine's messages start with the function's name).
    static void ExpectStatus(Status status, string needle, Action action)
    {
        try
        {
            action();
        }
        catch (FacesrException e)
        {
            Check(e.Status == status, "expected " + status + ", got " + e.Status + ": " + e.Message);
            Check(e.EngineMessage.Contains(needle), "message '" + e.EngineMessage + "' lacks '" + needle + "'");
            Check(e.Message.StartsWith(FacesrException.StatusName(status)), "message without the status name");
            return;
        }
        throw new CheckFailed("expected FacesrException(" + status + "), nothing was thrown");
    }

    static void ExpectThrows<T>(Action action) where T : Exception
    {
        try
        {
            action();
        }
        catch (T)
        {
            return;
        }
        catch (Exception e)
        {
            throw new CheckFailed("expected " + typeof(T).Name + ", got " + e.GetType().Name + ": " + e.Message);
        }
        throw new CheckFailed("expected " + typeof(T).Name + ", nothing was thrown");
    }

    static float MaxAbsDiff(float[] a, float[] b)
    {
        Check(a.Length == b.Length, "lengths differ");
        float worst = 0;
        for (int i = 0; i < a.Length; ++i) worst = Math.Max(worst, Math.Abs(a[i] - b[i]));
        return worst;
    }

    static bool AllFinite(float[] a)
    {
        foreach (float v in a)
            if (float.IsNaN(v) || float.IsInfinity(v)) return false;
        return true;
    }

    static Context NewContext(Rig rig, Model model)
    {
        // The CPU reference inference: deterministic, needs no OpenCL device.
        return new Context(rig, model, new ContextOptions { Inference = Inference.Cpu });
    }

    // --------------------------------------------------------- runner

    static int Main(string[] args)
    {
        if (args.Length != 2)
        {
            Console.Error.WriteLine("usage: FacesrTests.exe DATA_DIR OTHER_RIG");
            return 2;
        }
        dataDir = args[0];
        rigPath = Path.Combine(dataDir, "p.rig");
        modelPath = Path.Combine(dataDir, "p.fsm");
        otherRigPath = args[1];

        var tests = new List<KeyValuePair<string, Action>>
        {
            new KeyValuePair<string, Action>("LibraryAndStatusNames", LibraryAndStatusNames),
            new KeyValuePair<string, Action>("LoadErrors", LoadErrors),
            new KeyValuePair<string, Action>("RigAndModel", RigAndModel),
            new KeyValuePair<string, Action>("GeometryAndBufferSizes", GeometryAndBufferSizes),
            new KeyValuePair<string, Action>("ContextCreationErrors", ContextCreationErrors),
            new KeyValuePair<string, Action>("WeightsStepAndReadBack", WeightsStepAndReadBack),
            new KeyValuePair<string, Action>("OffsetsIntoLargerArrays", OffsetsIntoLargerArrays),
            new KeyValuePair<string, Action>("AsyncEqualsSync", AsyncEqualsSync),
            new KeyValuePair<string, Action>("SpringsAndSpheres", SpringsAndSpheres),
            new KeyValuePair<string, Action>("JawTransform", JawTransform),
            new KeyValuePair<string, Action>("DivergedFrameKeepsTheLastGoodSurface", DivergedFrameKeepsTheLastGoodSurface),
            new KeyValuePair<string, Action>("NullAndDisposedHandles", NullAndDisposedHandles),
            new KeyValuePair<string, Action>("ContextKeepsRigAndModelAlive", ContextKeepsRigAndModelAlive),
            new KeyValuePair<string, Action>("ContextsOnTwoThreads", ContextsOnTwoThreads),
            new KeyValuePair<string, Action>("HotPathDoesNotAllocate", HotPathDoesNotAllocate),
        };
        int failed = 0;
        foreach (var t in tests)
        {
            var watch = System.Diagnostics.Stopwatch.StartNew();
            try
            {
                t.Value();
                Console.WriteLine("[ OK ] " + t.Key + " (" + watch.ElapsedMilliseconds + " ms)");
            }
            catch (Exception e)
            {
                ++failed;
                Console.WriteLine("[FAIL] " + t.Key + ": " + e.GetType().Name + ": " + e.Message);
                Console.WriteLine(e.StackTrace);
            }
        }
        // Leftover handles are released by finalizers; run them now so that a
        // crash in ReleaseHandle shows up here, not after the verdict.
        GC.Collect();
        GC.WaitForPendingFinalizers();
        Console.WriteLine(failed == 0 ? "all " + tests.Count + " tests passed" : failed + " test(s) failed");
        return failed == 0 ? 0 : 1;
    }
}
