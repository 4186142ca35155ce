// FrameWriter.cs: the played surface, frame by frame, to
//   .bin  raw little-endian float32, frames x vertices x 3 (cm), nothing else:
//         the format the samples_agree test compares across C, C# and Rust;
//   .obj  one Wavefront object per frame ("o frame_0000"), each with its own
//         vertices (cm) and the rig's triangles.
// Written to OUT.partial and renamed when complete, so a failure never leaves
// a partial file under the requested name.
using System;
using System.Globalization;
using System.IO;
using System.Text;

namespace FacesrSample
{
    sealed class FrameWriter : IDisposable
    {
        readonly string path, partial;
        readonly bool obj;
        readonly int[] triangles;
        readonly int vertices;
        FileStream stream;
        BinaryWriter bin;
        StreamWriter text;
        byte[] bytes;  // one frame of .bin, reused
        int frames;

        public static bool Supports(string path)
        {
            string ext = Path.GetExtension(path).ToLowerInvariant();
            return ext == ".bin" || ext == ".obj";
        }

        public FrameWriter(string path, int vertices, int[] triangles)
        {
            this.path = path;
            partial = path + ".partial";
            obj = Path.GetExtension(path).ToLowerInvariant() == ".obj";
            this.vertices = vertices;
            this.triangles = triangles;
            stream = new FileStream(partial, FileMode.Create, FileAccess.Write);
            if (obj)
            {
                text = new StreamWriter(stream, new UTF8Encoding(false));
                text.WriteLine("# facesr_play_cs: one object per frame, positions in cm");
            }
            else
            {
                bin = new BinaryWriter(stream);
                bytes = new byte[12 * vertices];
            }
        }

        public void Write(float[] xyz)
        {
            if (obj)
            {
                text.WriteLine("o frame_" + frames.ToString("D4", CultureInfo.InvariantCulture));
                for (int i = 0; i < 3 * vertices; i += 3)
                    text.WriteLine("v " + F(xyz[i]) + " " + F(xyz[i + 1]) + " " + F(xyz[i + 2]));
                int first = frames * vertices + 1;  // OBJ indices are 1-based and global
                for (int t = 0; t < triangles.Length; t += 3)
                    text.WriteLine("f " + (first + triangles[t]) + " " + (first + triangles[t + 1]) + " " +
                                   (first + triangles[t + 2]));
            }
            else
            {
                // The float's bytes as they are in memory, swapped to
                // little-endian on a big-endian machine.
                Buffer.BlockCopy(xyz, 0, bytes, 0, bytes.Length);
                if (!BitConverter.IsLittleEndian)
                    for (int i = 0; i < bytes.Length; i += 4)
                    {
                        Array.Reverse(bytes, i, 4);
                    }
                bin.Write(bytes);
            }
            ++frames;
        }

        // "R" round-trips the float exactly.
        static string F(float v) { return v.ToString("R", CultureInfo.InvariantCulture); }

        // Flushes and renames the file into place.
        public void Commit()
        {
            if (obj) text.Flush();
            else bin.Flush();
            stream.Flush(true);
            stream.Dispose();
            stream = null;
            if (File.Exists(path)) File.Replace(partial, path, null);
            else File.Move(partial, path);
        }

        // Without Commit: the partial file is removed.
        public void Dispose()
        {
            if (stream == null) return;
            stream.Dispose();
            stream = null;
            try
            {
                File.Delete(partial);
            }
            catch (IOException)
            {
            }
        }
    }
}
