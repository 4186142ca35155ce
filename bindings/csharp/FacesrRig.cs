// FacesrRig.cs: the immutable rig and model. Both may be shared by any
// number of contexts on any threads (facesr.h); Dispose them after their
// contexts, or simply drop them: a context keeps its rig and model alive.
using System;
using System.Runtime.InteropServices;

namespace Facesr
{
    public sealed class Rig : IDisposable
    {
        readonly RigHandle handle;
        readonly RigInfo info;
        readonly string[] names;

        Rig(RigHandle h)
        {
            handle = h;
            info.StructSize = (uint)Marshal.SizeOf(typeof(RigInfo));
            FacesrException.Check(Native.facesr_rig_get_info(h, ref info));
            names = new string[info.NumBlendshapes];
            var buf = new byte[64];
            for (int i = 0; i < names.Length; ++i)
            {
                int length;
                FacesrException.Check(Native.facesr_rig_blendshape_name(h, i, buf, buf.Length, out length));
                if (length >= buf.Length)
                {
                    buf = new byte[length + 1];
                    FacesrException.Check(Native.facesr_rig_blendshape_name(h, i, buf, buf.Length, out length));
                }
                names[i] = System.Text.Encoding.UTF8.GetString(buf, 0, length);
            }
        }

        // Loads and validates a rig file (from `facesr rig build`). The path is
        // passed as UTF-8; on Windows keep it ASCII (see README).
        public static Rig Load(string path)
        {
            RigHandle h;
            int s = Native.facesr_rig_load(Utf8.Encode(path, "path"), out h);
            if (s != Native.FACESR_OK)
            {
                h.Dispose();
                FacesrException.Check(s);
            }
            try
            {
                return new Rig(h);
            }
            catch
            {
                h.Dispose();
                throw;
            }
        }

        // The raw handle, for Native calls. Throws once disposed.
        public RigHandle Handle
        {
            get
            {
                if (handle.IsClosed) throw new ObjectDisposedException("Facesr.Rig");
                return handle;
            }
        }

        // Read at load; valid after Dispose too.
        public RigInfo Info { get { return info; } }
        public int BlendshapeCount { get { return info.NumBlendshapes; } }
        public int VertexCount { get { return info.NumSurfaceVertices; } }
        public int TriangleCount { get { return info.NumSurfaceTriangles; } }
        // 3 * VertexCount: the length of a positions or normals buffer.
        public int PositionFloats { get { return 3 * info.NumSurfaceVertices; } }
        public ulong Checksum { get { return info.Checksum; } }

        // The blendshape names in rig order (ARKit names, case-sensitive).
        public string BlendshapeName(int index)
        {
            if (index < 0 || index >= names.Length)
                throw new ArgumentOutOfRangeException("index", index, "no blendshape " + index + " in this rig");
            return names[index];
        }

        public string[] BlendshapeNames() { return (string[])names.Clone(); }

        // Index of a blendshape by exact name; FacesrException(NotFound) if none.
        public int BlendshapeIndex(string name)
        {
            int index;
            FacesrException.Check(Native.facesr_rig_blendshape_index(Handle, Utf8.Encode(name, "name"), out index));
            return index;
        }

        // Like BlendshapeIndex, without the exception; no library call.
        public bool TryGetBlendshapeIndex(string name, out int index)
        {
            index = name == null ? -1 : Array.IndexOf(names, name);
            return index >= 0;
        }

        // The surface's triangle indices, counter-clockwise seen from outside
        // (3 * TriangleCount). They never change: read them once.
        public int[] GetTriangles()
        {
            var t = new int[3 * info.NumSurfaceTriangles];
            GetTriangles(t);
            return t;
        }

        // indices.Length must be 3 * TriangleCount (else BufferSize).
        public void GetTriangles(int[] indices)
        {
            if (indices == null) throw new ArgumentNullException("indices");
            FacesrException.Check(Native.facesr_rig_get_triangles(Handle, indices, indices.LongLength));
        }

        // Rest positions of the surface (cm); xyz.Length must be PositionFloats.
        public void GetRestPositions(float[] xyz)
        {
            if (xyz == null) throw new ArgumentNullException("xyz");
            FacesrException.Check(Native.facesr_rig_get_rest_positions(Handle, xyz, xyz.LongLength));
        }

        public float[] GetRestPositions()
        {
            var xyz = new float[PositionFloats];
            GetRestPositions(xyz);
            return xyz;
        }

        public void Dispose() { handle.Dispose(); }
    }

    public sealed class Model : IDisposable
    {
        readonly ModelHandle handle;
        readonly ModelInfo info;

        Model(ModelHandle h)
        {
            handle = h;
            info.StructSize = (uint)Marshal.SizeOf(typeof(ModelInfo));
            FacesrException.Check(Native.facesr_model_get_info(h, ref info));
        }

        // Loads and validates a super-resolution model (from `facesr train`).
        public static Model Load(string path)
        {
            ModelHandle h;
            int s = Native.facesr_model_load(Utf8.Encode(path, "path"), out h);
            if (s != Native.FACESR_OK)
            {
                h.Dispose();
                FacesrException.Check(s);
            }
            try
            {
                return new Model(h);
            }
            catch
            {
                h.Dispose();
                throw;
            }
        }

        public ModelHandle Handle
        {
            get
            {
                if (handle.IsClosed) throw new ObjectDisposedException("Facesr.Model");
                return handle;
            }
        }

        public ModelInfo Info { get { return info; } }
        // The checksum of the rig the model was trained on (Rig.Checksum).
        public ulong RigChecksum { get { return info.RigChecksum; } }

        public void Dispose() { handle.Dispose(); }
    }
}
