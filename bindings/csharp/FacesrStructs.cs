// FacesrStructs.cs: the structs of facesr.h, field for field.
//
// Each is blittable (only int, uint, long, ulong, float, IntPtr and Float3
// fields, LayoutKind.Sequential), so the marshaller passes a pointer to the
// managed struct itself: no copy, no allocation. C arrays `float x[3]` are a
// Float3 (three consecutive floats, the same bytes), which needs no `unsafe`
// code, so Unity projects need not enable it.
//
// Field names are the C names in PascalCase (num_lr_nodes -> NumLrNodes) and
// [NativeStruct] gives the C type name: the consistency check relies on both
// to compare Marshal.OffsetOf / SizeOf with the C compiler's offsetof and
// sizeof.
using System;
using System.Runtime.InteropServices;

namespace Facesr
{
    // Marks a struct as the mirror of the named facesr.h struct.
    [AttributeUsage(AttributeTargets.Struct)]
    public sealed class NativeStructAttribute : Attribute
    {
        public readonly string Name;
        public NativeStructAttribute(string name) { Name = name; }
    }

    // A point or direction in the rig's rest frame (cm): C `float v[3]`.
    [StructLayout(LayoutKind.Sequential)]
    public struct Float3
    {
        public float X, Y, Z;
        public Float3(float x, float y, float z) { X = x; Y = y; Z = z; }
        public override string ToString() { return "(" + X + ", " + Y + ", " + Z + ")"; }
    }

    [NativeStruct("facesr_rig_info")]
    [StructLayout(LayoutKind.Sequential)]
    public struct RigInfo
    {
        public uint StructSize;         // sizeof(facesr_rig_info); set by Rig.Info
        public int NumBlendshapes;      // ARKit-named controls, in rig order
        public int NumSurfaceVertices;  // M: vertices of the output surface
        public int NumSurfaceTriangles;
        public int NumLrNodes;          // N: nodes of the LR simulation lattice
        public int NumMuscles;
        public ulong Checksum;          // identifies the rig; a model records the one it was trained on
        public Float3 JawPivot;         // a point on the jaw hinge axis (cm)
        public Float3 JawAxis;          // unit hinge axis; a positive angle opens the mouth
    }

    [NativeStruct("facesr_model_info")]
    [StructLayout(LayoutKind.Sequential)]
    public struct ModelInfo
    {
        public uint StructSize;
        public ulong RigChecksum;
        public int NumLrNodes;
        public int NumSurfaceVertices;
        public int NumParameters;       // trainable scalars
    }

    // Build with Native.facesr_default_context_def() (ContextOptions does):
    // a zeroed struct has struct_size 0, which the library refuses.
    [NativeStruct("facesr_context_def")]
    [StructLayout(LayoutKind.Sequential)]
    public struct ContextDef
    {
        public uint StructSize;
        public int DeviceIndex;         // `facesr devices` index; -1: by name or default
        public IntPtr DeviceName;       // NUL-terminated UTF-8, or IntPtr.Zero for the default (first CPU device)
        public int Solver;              // FACESR_SOLVER_*
        public int Inference;           // FACESR_INFERENCE_*
        public int SplitDevice;         // nonzero: half the device per stage (for StepAsync)
        public int LrPrecision;         // FACESR_PRECISION_*
    }

    // A spring pulling one surface vertex toward a target. Start from
    // SpringDef.Default (the library's defaults, struct_size set).
    [NativeStruct("facesr_spring_def")]
    [StructLayout(LayoutKind.Sequential)]
    public struct SpringDef
    {
        public uint StructSize;
        public int Vertex;              // output-surface vertex index (the default -1 must be replaced)
        public Float3 Target;           // cm, rest frame
        public float Stiffness;         // kPa·cm, > 0

        public static SpringDef Default { get { return Native.facesr_default_spring_def(); } }
    }

    // A kinematic sphere pushing the face away. Start from SphereDef.Default.
    [NativeStruct("facesr_sphere_def")]
    [StructLayout(LayoutKind.Sequential)]
    public struct SphereDef
    {
        public uint StructSize;
        public Float3 Centre;           // cm, rest frame
        public float Radius;            // cm, > 0
        public float Stiffness;         // kPa·cm, > 0

        public static SphereDef Default { get { return Native.facesr_default_sphere_def(); } }
    }

    [NativeStruct("facesr_frame_stats")]
    [StructLayout(LayoutKind.Sequential)]
    public struct FrameStats
    {
        public uint StructSize;
        public long Frame;              // 0, 1, ... in stepping order; -1 before the first step
        public float SimulationMs;      // LR simulation of this frame
        public float InferenceMs;       // super-resolution of this frame
        public float TotalMs;           // start to results (sync), or submit to done (async)
        public int NewtonIterations;
        public int CgIterations;
        public float RelativeResidual;  // of the LR solve
        public int SimulationStatus;    // FrameStatus: Diverged means the last good surface was returned
        public int InvertedTets;        // LR tets inverted in the kept solve
        public int Recoveries;          // extra solves the recovery ran

        public FrameStatus Status { get { return (FrameStatus)SimulationStatus; } }
    }

    // FACESR_FRAME_* of capi/facesr.h.
    public enum FrameStatus
    {
        Converged = Native.FACESR_FRAME_CONVERGED,      // reached the solver's tolerance
        Unconverged = Native.FACESR_FRAME_UNCONVERGED,  // stopped at the iteration cap above tolerance (normal for real time)
        Recovered = Native.FACESR_FRAME_RECOVERED,      // diverged at first, solved by the recovery
        Diverged = Native.FACESR_FRAME_DIVERGED,        // recovery failed: the last good surface is returned
    }
}
