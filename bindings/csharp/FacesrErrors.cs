// FacesrErrors.cs: statuses as exceptions, and UTF-8 strings across the
// boundary.
using System;
using System.Runtime.InteropServices;
using System.Text;

namespace Facesr
{
    // facesr_status. The values are the FACESR_* codes of facesr.h.
    public enum Status
    {
        Ok = Native.FACESR_OK,
        NullArgument = Native.FACESR_ERROR_NULL_ARGUMENT,
        InvalidArgument = Native.FACESR_ERROR_INVALID_ARGUMENT,
        BufferSize = Native.FACESR_ERROR_BUFFER_SIZE,
        File = Native.FACESR_ERROR_FILE,
        Mismatch = Native.FACESR_ERROR_MISMATCH,
        Device = Native.FACESR_ERROR_DEVICE,
        NotFound = Native.FACESR_ERROR_NOT_FOUND,
        State = Native.FACESR_ERROR_STATE,
        Simulation = Native.FACESR_ERROR_SIMULATION,
        Internal = Native.FACESR_ERROR_INTERNAL,
    }

    // A failed library call: the status and the engine's message, e.g.
    // "facesr_get_positions: xyz has 10 elements; 2610 (3 * num_surface_vertices) are required".
    // The object the call was made on is unchanged and still usable.
    public class FacesrException : Exception
    {
        public readonly Status Status;
        public readonly string EngineMessage;

        public FacesrException(Status status, string engineMessage)
            : base(StatusName(status) + ": " + engineMessage)
        {
            Status = status;
            EngineMessage = engineMessage;
        }

        // "FACESR_ERROR_BUFFER_SIZE" (facesr_status_name).
        public static string StatusName(Status status)
        {
            return Utf8.Decode(Native.facesr_status_name((int)status));
        }

        // Throws for a failed status. The message is the calling thread's, read
        // at once: P/Invoke returns on the thread that made the call.
        internal static void Check(int status)
        {
            if (status != Native.FACESR_OK)
                throw new FacesrException((Status)status, Utf8.Decode(Native.facesr_last_error_message()));
        }
    }

    // UTF-8, the library's encoding for every string.
    public static class Utf8
    {
        // NUL-terminated UTF-8 bytes of s. A string holding '\0' would be cut
        // short by the library, so it is refused.
        public static byte[] Encode(string s, string what)
        {
            if (s == null) throw new ArgumentNullException(what);
            if (s.IndexOf('\0') >= 0) throw new ArgumentException(what + " contains a NUL character", what);
            int n = Encoding.UTF8.GetByteCount(s);
            var bytes = new byte[n + 1];
            Encoding.UTF8.GetBytes(s, 0, s.Length, bytes, 0);
            return bytes;
        }

        // Encodes s into buffer (grown when too small) without allocating once
        // it is large enough: for names set every frame.
        public static void EncodeInto(string s, string what, ref byte[] buffer)
        {
            if (s == null) throw new ArgumentNullException(what);
            if (s.IndexOf('\0') >= 0) throw new ArgumentException(what + " contains a NUL character", what);
            int max = Encoding.UTF8.GetMaxByteCount(s.Length) + 1;
            if (buffer == null || buffer.Length < max)
            {
                int n = Encoding.UTF8.GetByteCount(s) + 1;
                if (buffer == null || buffer.Length < n) buffer = new byte[Math.Max(n, 64)];
            }
            int written = Encoding.UTF8.GetBytes(s, 0, s.Length, buffer, 0);
            buffer[written] = 0;
        }

        // A NUL-terminated UTF-8 string owned by the library ("" for NULL).
        // Marshal.PtrToStringAnsi would use the ANSI code page on Windows.
        public static string Decode(IntPtr p)
        {
            if (p == IntPtr.Zero) return "";
            int n = 0;
            while (Marshal.ReadByte(p, n) != 0) ++n;
            if (n == 0) return "";
            var bytes = new byte[n];
            Marshal.Copy(p, bytes, 0, n);
            return Encoding.UTF8.GetString(bytes);
        }
    }
}

namespace Facesr
{
    // The library as a whole.
    public static class FacesrLibrary
    {
        // FACESR_ABI_VERSION of the loaded library.
        public static uint AbiVersion { get { return Native.facesr_abi_version(); } }

        // "facesr 0.1.0".
        public static string VersionString { get { return Utf8.Decode(Native.facesr_version_string()); } }

        // Throws if the loaded native library was built for another ABI than
        // these bindings (an old libfacesr left in Plugins/, say).
        public static void EnsureCompatible()
        {
            uint abi = AbiVersion;
            if (abi != Native.FACESR_ABI_VERSION)
                throw new InvalidOperationException("the native facesr library has ABI " + abi +
                                                    "; these bindings are for ABI " + Native.FACESR_ABI_VERSION);
        }
    }
}
