// FacesrNative.cs: the raw P/Invoke layer over capi/facesr.h, one
// declaration per header function, constants under their C names, and the
// header's structs as blittable sequential structs.
//
// The safe API (Rig, Model, Context) sits on top of this; use Native directly
// only for what it does not cover. The test bindings_consistency compares
// every declaration here with the header (names, parameter kinds, struct
// sizes and offsets), so keep it a plain mirror of facesr.h.
//
// Conventions, so that nothing allocates on the managed heap per call:
// - Handles are SafeHandle subclasses: the marshaller keeps them alive for
//   the call and refuses closed ones.
// - Buffers are float[] / int[] (pinned by the marshaller, no copy), or
//   `ref float` to the first element for an offset into a larger array, or
//   IntPtr for memory the caller pinned (a Unity NativeArray, a pinned
//   Vector3[]).
// - Strings are never marshalled as `string`: .NET Framework marshals it in
//   the ANSI code page on Windows, while the library reads UTF-8. Names and
//   paths go in as NUL-terminated UTF-8 byte[] (Utf8.Encode); const char*
//   results come back as IntPtr (static or library-owned storage the
//   marshaller must not free) and are decoded by Utf8.Decode.
// - Every function is cdecl, as facesr.h declares them (no calling
//   convention macro, so the platform C default; on Windows x86 that is
//   cdecl, elsewhere there is only one).
using System;
using System.Runtime.InteropServices;

namespace Facesr
{
    public static class Native
    {
        // The library's base name: DllImport finds facesr.dll, libfacesr.so
        // and libfacesr.dylib from it (Unity: Assets/Plugins/<platform>/).
        public const string Library = "facesr";

        public const int FACESR_ABI_VERSION = 1;

        public const int FACESR_OK = 0;
        public const int FACESR_ERROR_NULL_ARGUMENT = 1;
        public const int FACESR_ERROR_INVALID_ARGUMENT = 2;
        public const int FACESR_ERROR_BUFFER_SIZE = 3;
        public const int FACESR_ERROR_FILE = 4;
        public const int FACESR_ERROR_MISMATCH = 5;
        public const int FACESR_ERROR_DEVICE = 6;
        public const int FACESR_ERROR_NOT_FOUND = 7;
        public const int FACESR_ERROR_STATE = 8;
        public const int FACESR_ERROR_SIMULATION = 9;
        public const int FACESR_ERROR_INTERNAL = 10;

        public const int FACESR_SOLVER_REALTIME = 0;
        public const int FACESR_SOLVER_ACCURATE = 1;

        public const int FACESR_PRECISION_AUTO = 0;
        public const int FACESR_PRECISION_DOUBLE = 1;
        public const int FACESR_PRECISION_FLOAT = 2;

        public const int FACESR_INFERENCE_OPENCL = 0;
        public const int FACESR_INFERENCE_CPU = 1;

        public const int FACESR_FRAME_CONVERGED = 0;
        public const int FACESR_FRAME_UNCONVERGED = 1;
        public const int FACESR_FRAME_RECOVERED = 2;
        public const int FACESR_FRAME_DIVERGED = 3;

        // ------------------------------------------------------------ status

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern uint facesr_abi_version();

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern IntPtr facesr_version_string();

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern IntPtr facesr_last_error_message();

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern IntPtr facesr_status_name(int status);

        // --------------------------------------------------------------- rig

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern int facesr_rig_load(byte[] utf8Path, out RigHandle outRig);

        // Called by RigHandle.ReleaseHandle only.
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern void facesr_rig_free(IntPtr rig);

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern int facesr_rig_get_info(RigHandle rig, ref RigInfo info);

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern int facesr_rig_blendshape_name(RigHandle rig, int index, byte[] buf, int bufSize,
                                                            out int outLength);

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern int facesr_rig_blendshape_index(RigHandle rig, byte[] utf8Name, out int outIndex);

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern int facesr_rig_get_triangles(RigHandle rig, int[] indices, long count);

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern int facesr_rig_get_rest_positions(RigHandle rig, float[] xyz, long count);

        // ------------------------------------------------------------- model

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern int facesr_model_load(byte[] utf8Path, out ModelHandle outModel);

        // Called by ModelHandle.ReleaseHandle only.
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern void facesr_model_free(IntPtr model);

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern int facesr_model_get_info(ModelHandle model, ref ModelInfo info);

        // ----------------------------------------------------------- context

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern ContextDef facesr_default_context_def();

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern int facesr_context_create(RigHandle rig, ModelHandle model, ref ContextDef def,
                                                       out ContextHandle outContext);

        // def NULL: every field at its default.
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern int facesr_context_create(RigHandle rig, ModelHandle model, IntPtr def,
                                                       out ContextHandle outContext);

        // Called by ContextHandle.ReleaseHandle only.
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern void facesr_context_destroy(IntPtr context);

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern int facesr_context_reset(ContextHandle context);

        // ---------------------------------------------------------- controls

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern int facesr_set_weight(ContextHandle context, int index, float value);

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern int facesr_set_weight_by_name(ContextHandle context, byte[] utf8Name, float value);

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern int facesr_set_weights(ContextHandle context, float[] weights, long count);

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern int facesr_set_weights(ContextHandle context, ref float weights, long count);

        // rotation: 9 floats, row-major.
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern int facesr_set_jaw_transform(ContextHandle context, float[] rotation,
                                                          ref Float3 translation);

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern int facesr_clear_jaw_transform(ContextHandle context);

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern SpringDef facesr_default_spring_def();

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern SphereDef facesr_default_sphere_def();

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern int facesr_add_spring(ContextHandle context, ref SpringDef def, out int outId);

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern int facesr_move_spring(ContextHandle context, int id, ref Float3 target);

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern int facesr_remove_spring(ContextHandle context, int id);

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern int facesr_add_sphere(ContextHandle context, ref SphereDef def, out int outId);

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern int facesr_move_sphere(ContextHandle context, int id, ref Float3 centre);

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern int facesr_remove_sphere(ContextHandle context, int id);

        // ---------------------------------------------------------- stepping

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern int facesr_step(ContextHandle context);

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern int facesr_step_async(ContextHandle context);

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern int facesr_wait(ContextHandle context, out long outFrame);

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern int facesr_pending_frames(ContextHandle context, out int outCount);

        // --------------------------------------------------------- read-back
        // Three forms each: a whole array, an offset into one (ref to its
        // first element), or caller-pinned memory.

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern int facesr_get_positions(ContextHandle context, float[] xyz, long count);

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern int facesr_get_positions(ContextHandle context, ref float xyz, long count);

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern int facesr_get_positions(ContextHandle context, IntPtr xyz, long count);

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern int facesr_get_normals(ContextHandle context, float[] xyz, long count);

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern int facesr_get_normals(ContextHandle context, ref float xyz, long count);

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern int facesr_get_normals(ContextHandle context, IntPtr xyz, long count);

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern int facesr_get_embedded_positions(ContextHandle context, float[] xyz, long count);

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern int facesr_get_embedded_positions(ContextHandle context, ref float xyz, long count);

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern int facesr_get_embedded_positions(ContextHandle context, IntPtr xyz, long count);

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern int facesr_get_frame_stats(ContextHandle context, ref FrameStats stats);
    }
}
