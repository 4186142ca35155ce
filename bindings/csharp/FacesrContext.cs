// FacesrContext.cs: one face's mutable state, stepped every frame.
//
// Threading (facesr.h): use a context from one thread at a time; different
// contexts may run concurrently. StepAsync runs the frame on the context's
// own worker threads; call Wait from the thread that owns the context.
//
// The per-frame calls (SetWeight, SetWeights, Step, StepAsync, Wait,
// GetPositions, GetNormals, GetFrameStats) allocate nothing on the managed
// heap: buffers are the caller's and reused, names are encoded into a
// buffer the context keeps.
using System;
using System.Runtime.InteropServices;

namespace Facesr
{
    public enum Solver
    {
        Realtime = Native.FACESR_SOLVER_REALTIME,  // at most 3 Newton steps of 60 CG iterations (default)
        Accurate = Native.FACESR_SOLVER_ACCURATE,  // Newton to a 1e-3 relative residual (offline)
    }

    // The LR simulation's arithmetic (the inference is always float).
    public enum Precision
    {
        Auto = Native.FACESR_PRECISION_AUTO,      // float with the realtime solver, double with accurate (default)
        Double = Native.FACESR_PRECISION_DOUBLE,
        Float = Native.FACESR_PRECISION_FLOAT,
    }

    public enum Inference
    {
        OpenCL = Native.FACESR_INFERENCE_OPENCL,   // the OpenCL kernels (default)
        Cpu = Native.FACESR_INFERENCE_CPU,         // the plain C++ reference (slow; for checks)
    }

    // What facesr_context_def holds, as managed values.
    public sealed class ContextOptions
    {
        public int DeviceIndex = -1;       // `facesr devices` index; -1: by name or default
        public string DeviceName;          // substring of the device or platform name; null: first CPU device
        public Solver Solver = Solver.Realtime;
        public Inference Inference = Inference.OpenCL;
        public bool SplitDevice;           // half the device each for simulation and inference (faster with StepAsync)
        public Precision LrPrecision = Precision.Auto;
    }

    public sealed class Context : IDisposable
    {
        readonly ContextHandle handle;
        readonly Rig rig;
        readonly Model model;
        readonly int positionFloats, blendshapes;
        byte[] nameBuffer = new byte[64];  // UTF-8 of the last name set by SetWeight(string, ...)

        // A context for one face. The model must have been trained on this rig
        // (FacesrException Mismatch otherwise).
        public Context(Rig rig, Model model, ContextOptions options = null)
        {
            if (rig == null) throw new ArgumentNullException("rig");
            if (model == null) throw new ArgumentNullException("model");
            ContextDef def = Native.facesr_default_context_def();
            IntPtr name = IntPtr.Zero;
            try
            {
                if (options != null)
                {
                    def.DeviceIndex = options.DeviceIndex;
                    def.Solver = (int)options.Solver;
                    def.Inference = (int)options.Inference;
                    def.SplitDevice = options.SplitDevice ? 1 : 0;
                    def.LrPrecision = (int)options.LrPrecision;
                    if (options.DeviceName != null)
                    {
                        byte[] utf8 = Utf8.Encode(options.DeviceName, "options.DeviceName");
                        name = Marshal.AllocHGlobal(utf8.Length);
                        Marshal.Copy(utf8, 0, name, utf8.Length);
                        def.DeviceName = name;
                    }
                }
                ContextHandle h;
                int s;
                lock (CreateLock) s = Native.facesr_context_create(rig.Handle, model.Handle, ref def, out h);
                if (s != Native.FACESR_OK)
                {
                    h.Dispose();
                    FacesrException.Check(s);
                }
                try
                {
                    h.HoldParents(rig.Handle, model.Handle);
                }
                catch
                {
                    h.Dispose();
                    throw;
                }
                handle = h;
            }
            finally
            {
                if (name != IntPtr.Zero) Marshal.FreeHGlobal(name);
            }
            this.rig = rig;
            this.model = model;
            positionFloats = rig.PositionFloats;
            blendshapes = rig.BlendshapeCount;
        }

        public ContextHandle Handle
        {
            get
            {
                if (handle.IsClosed) throw new ObjectDisposedException("Facesr.Context");
                return handle;
            }
        }

        public Rig Rig { get { return rig; } }
        public Model Model { get { return model; } }
        // 3 * vertices: the length of a positions or normals buffer.
        public int PositionFloats { get { return positionFloats; } }

        // Back to the rest pose: controls cleared, springs and spheres removed,
        // pending frames dropped.
        public void Reset() { FacesrException.Check(Native.facesr_context_reset(Handle)); }

        // ------------------------------------------------------ controls
        // They take effect at the next Step / StepAsync.

        // Weight in [0, 1] of the blendshape at index (rig order).
        public void SetWeight(int index, float value)
        {
            FacesrException.Check(Native.facesr_set_weight(Handle, index, value));
        }

        // By exact (case-sensitive, ASCII ARKit) name, e.g. "jawOpen".
        public void SetWeight(string name, float value)
        {
            Utf8.EncodeInto(name, "name", ref nameBuffer);
            FacesrException.Check(Native.facesr_set_weight_by_name(Handle, nameBuffer, value));
        }

        // All weights at once: weights.Length must be Rig.BlendshapeCount.
        // Nothing changes if any value is bad.
        public void SetWeights(float[] weights)
        {
            if (weights == null) throw new ArgumentNullException("weights");
            FacesrException.Check(Native.facesr_set_weights(Handle, weights, weights.LongLength));
        }

        // Rig.BlendshapeCount weights starting at weights[offset] (a row of a
        // frames x blendshapes table).
        public void SetWeights(float[] weights, int offset)
        {
            CheckRange(weights, offset, blendshapes, "weights");
            FacesrException.Check(Native.facesr_set_weights(Handle, ref weights[offset], blendshapes));
        }

        // Explicit rigid jaw motion x' = R x + t: rotation row-major (9
        // floats, a proper rotation), translation in cm.
        public void SetJawTransform(float[] rotation, Float3 translation)
        {
            if (rotation == null) throw new ArgumentNullException("rotation");
            if (rotation.Length != 9)
                throw new ArgumentException("rotation has " + rotation.Length + " elements; 9 are required", "rotation");
            FacesrException.Check(Native.facesr_set_jaw_transform(Handle, rotation, ref translation));
        }

        // The jaw follows the blendshape weights again.
        public void ClearJawTransform() { FacesrException.Check(Native.facesr_clear_jaw_transform(Handle)); }

        // ---------------------------------------------- springs, spheres
        // Ids are positive and never reused within a context.

        public int AddSpring(SpringDef def)
        {
            int id;
            FacesrException.Check(Native.facesr_add_spring(Handle, ref def, out id));
            return id;
        }

        // A spring from the library's defaults with these fields.
        public int AddSpring(int vertex, Float3 target, float stiffness)
        {
            SpringDef def = SpringDef.Default;
            def.Vertex = vertex;
            def.Target = target;
            def.Stiffness = stiffness;
            return AddSpring(def);
        }

        public void MoveSpring(int id, Float3 target)
        {
            FacesrException.Check(Native.facesr_move_spring(Handle, id, ref target));
        }

        public void RemoveSpring(int id) { FacesrException.Check(Native.facesr_remove_spring(Handle, id)); }

        public int AddSphere(SphereDef def)
        {
            int id;
            FacesrException.Check(Native.facesr_add_sphere(Handle, ref def, out id));
            return id;
        }

        public int AddSphere(Float3 centre, float radius, float stiffness)
        {
            SphereDef def = SphereDef.Default;
            def.Centre = centre;
            def.Radius = radius;
            def.Stiffness = stiffness;
            return AddSphere(def);
        }

        public void MoveSphere(int id, Float3 centre)
        {
            FacesrException.Check(Native.facesr_move_sphere(Handle, id, ref centre));
        }

        public void RemoveSphere(int id) { FacesrException.Check(Native.facesr_remove_sphere(Handle, id)); }

        // ------------------------------------------------------ stepping

        // One frame with the current controls; results readable on return.
        // Not while asynchronous frames are pending (State).
        public void Step() { FacesrException.Check(Native.facesr_step(Handle)); }

        // Queues a frame (controls copied) and returns at once; at most 2
        // pending. Wait returns them in order.
        public void StepAsync() { FacesrException.Check(Native.facesr_step_async(Handle)); }

        // Blocks for the oldest pending frame and makes it the readable one;
        // returns its frame number. State when nothing is pending.
        public long Wait()
        {
            long frame;
            FacesrException.Check(Native.facesr_wait(Handle, out frame));
            return frame;
        }

        public int PendingFrames
        {
            get
            {
                int n;
                FacesrException.Check(Native.facesr_pending_frames(Handle, out n));
                return n;
            }
        }

        // ----------------------------------------------------- read-back
        // Of the latest readable frame (before the first step: the rest pose).
        // xyz.Length must be PositionFloats; the offset forms write
        // PositionFloats floats from xyz[offset] (e.g. frame f of a
        // frames x vertices x 3 table); the IntPtr forms write count floats to
        // memory the caller pinned.

        public void GetPositions(float[] xyz)
        {
            if (xyz == null) throw new ArgumentNullException("xyz");
            FacesrException.Check(Native.facesr_get_positions(Handle, xyz, xyz.LongLength));
        }

        public void GetPositions(float[] xyz, int offset)
        {
            CheckRange(xyz, offset, positionFloats, "xyz");
            FacesrException.Check(Native.facesr_get_positions(Handle, ref xyz[offset], positionFloats));
        }

        public void GetPositions(IntPtr xyz, long count)
        {
            FacesrException.Check(Native.facesr_get_positions(Handle, xyz, count));
        }

        // Unit area-weighted vertex normals of the same surface.
        public void GetNormals(float[] xyz)
        {
            if (xyz == null) throw new ArgumentNullException("xyz");
            FacesrException.Check(Native.facesr_get_normals(Handle, xyz, xyz.LongLength));
        }

        public void GetNormals(float[] xyz, int offset)
        {
            CheckRange(xyz, offset, positionFloats, "xyz");
            FacesrException.Check(Native.facesr_get_normals(Handle, ref xyz[offset], positionFloats));
        }

        public void GetNormals(IntPtr xyz, long count)
        {
            FacesrException.Check(Native.facesr_get_normals(Handle, xyz, count));
        }

        // The surface carried by the LR lattice alone (no super-resolution).
        public void GetEmbeddedPositions(float[] xyz)
        {
            if (xyz == null) throw new ArgumentNullException("xyz");
            FacesrException.Check(Native.facesr_get_embedded_positions(Handle, xyz, xyz.LongLength));
        }

        public void GetEmbeddedPositions(float[] xyz, int offset)
        {
            CheckRange(xyz, offset, positionFloats, "xyz");
            FacesrException.Check(Native.facesr_get_embedded_positions(Handle, ref xyz[offset], positionFloats));
        }

        public FrameStats GetFrameStats()
        {
            var stats = new FrameStats();  // a struct: on the stack
            stats.StructSize = FrameStatsSize;
            FacesrException.Check(Native.facesr_get_frame_stats(Handle, ref stats));
            return stats;
        }

        // Waits for pending frames and frees the context. The rig and model
        // stay until they are disposed too.
        public void Dispose() { handle.Dispose(); }

        // Serializes facesr_context_create within the process: OpenCL drivers'
        // first queries are not always thread-safe (PoCL's device enumeration
        // was not; the library now serialises that itself). A cheap guard for
        // the rest of context creation; everything else stays concurrent.
        static readonly object CreateLock = new object();

        static readonly uint FrameStatsSize = (uint)Marshal.SizeOf(typeof(FrameStats));

        // The native side cannot know a managed array's length: check that
        // `count` floats from `offset` lie inside it before passing a pointer.
        static void CheckRange(float[] a, int offset, int count, string what)
        {
            if (a == null) throw new ArgumentNullException(what);
            if (offset < 0 || count <= 0 || offset > a.Length - count)
                throw new ArgumentOutOfRangeException(
                    what, what + "[" + offset + " .. " + ((long)offset + count) + ") is outside an array of " +
                              a.Length + " floats");
        }
    }
}
