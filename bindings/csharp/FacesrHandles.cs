// FacesrHandles.cs: SafeHandles owning the library's objects. ReleaseHandle
// runs exactly once (Dispose or the finalizer thread) and calls the
// matching free/destroy function.
using System;
using System.Runtime.InteropServices;

namespace Facesr
{
    // An immutable rig (facesr_rig*): shareable across threads and contexts.
    public sealed class RigHandle : SafeHandle
    {
        // Used by the marshaller for `out RigHandle`.
        public RigHandle() : base(IntPtr.Zero, true) { }

        public override bool IsInvalid { get { return handle == IntPtr.Zero; } }

        protected override bool ReleaseHandle()
        {
            Native.facesr_rig_free(handle);
            return true;
        }
    }

    // An immutable super-resolution model (facesr_model*): shareable.
    public sealed class ModelHandle : SafeHandle
    {
        public ModelHandle() : base(IntPtr.Zero, true) { }

        public override bool IsInvalid { get { return handle == IntPtr.Zero; } }

        protected override bool ReleaseHandle()
        {
            Native.facesr_model_free(handle);
            return true;
        }
    }

    // One face's mutable state (facesr_context*): one thread at a time.
    //
    // facesr.h asks for contexts to be destroyed before their rig and model.
    // Finalizers run in no particular order, so the context handle holds a
    // reference count on both (SafeHandle.DangerousAddRef): they are freed only
    // after the context, however the objects are dropped.
    public sealed class ContextHandle : SafeHandle
    {
        SafeHandle rig, model;

        public ContextHandle() : base(IntPtr.Zero, true) { }

        public override bool IsInvalid { get { return handle == IntPtr.Zero; } }

        // Called once, right after a successful facesr_context_create.
        internal void HoldParents(RigHandle rigHandle, ModelHandle modelHandle)
        {
            bool rigAdded = false, modelAdded = false;
            try
            {
                rigHandle.DangerousAddRef(ref rigAdded);
                modelHandle.DangerousAddRef(ref modelAdded);
            }
            finally
            {
                if (rigAdded) rig = rigHandle;
                if (modelAdded) model = modelHandle;
            }
        }

        protected override bool ReleaseHandle()
        {
            Native.facesr_context_destroy(handle);
            if (rig != null) rig.DangerousRelease();
            if (model != null) model.DangerousRelease();
            rig = model = null;
            return true;
        }
    }
}
