// Performance.cs: a keyframe performance file (format "facesr-performance",
// version 1, docs/performances.md) sampled into per-frame weights exactly as
// the engine and the C sample (samples/c/performance.c) do: frame f at
// t_first + f / fps up to the last keyframe, linear interpolation in double,
// a shape a keyframe does not list is 0 there. Doing the arithmetic the same
// way is what lets the three samples produce the same surfaces.
using System;
using System.Collections.Generic;
using System.IO;
using System.Text;

namespace FacesrSample
{
    sealed class Performance
    {
        const double MaxFps = 1000, MaxFrames = 3e6;  // the engine's bounds

        public double Fps;
        public int Frames;
        public string[] Names;  // every blendshape some keyframe lists, in order of first appearance
        public float[] Weights; // Frames x Names.Length, row-major
        public bool HasJaw;     // explicit jaw transforms (not played, as in the C sample)

        // Throws InvalidDataException "path: problem".
        public static Performance Load(string path)
        {
            string text;
            try
            {
                // Invalid UTF-8 is replaced rather than refused: such a name
                // matches no rig name and is reported as unknown later.
                text = Encoding.UTF8.GetString(File.ReadAllBytes(path));
            }
            catch (Exception e) when (e is IOException || e is UnauthorizedAccessException)
            {
                throw new InvalidDataException(path + ": cannot read the performance file (" + e.Message + ")");
            }
            JsonValue root;
            try
            {
                root = JsonParser.Parse(text);
            }
            catch (JsonException e)
            {
                throw new InvalidDataException(path + ": not valid JSON: " + e.Message);
            }
            return Build(root, path);
        }

        static InvalidDataException Bad(string path, string what) { return new InvalidDataException(path + ": " + what); }

        static Performance Build(JsonValue root, string path)
        {
            if (root.Type != JsonType.Object) throw Bad(path, "is not a JSON object");
            JsonValue format = root.Get("format"), version = root.Get("version"), fps = root.Get("fps"),
                      jk = root.Get("keyframes");
            if (format == null || format.Type != JsonType.String || format.String != "facesr-performance")
                throw Bad(path, "'format' is not \"facesr-performance\"");
            if (version == null || version.Type != JsonType.Number || version.Number != 1)
                throw Bad(path, "'version' is missing or not 1");
            if (fps == null || fps.Type != JsonType.Number || !(fps.Number > 0 && fps.Number <= MaxFps))
                throw Bad(path, "'fps' is missing or not in (0, 1000]");
            if (jk == null || jk.Type != JsonType.Array || jk.Items.Count == 0)
                throw Bad(path, "'keyframes' is missing, not an array, or empty");

            var perf = new Performance { Fps = fps.Number };
            // Every listed name first, so that each keyframe's row has them all.
            var names = new List<string>();
            var slot = new Dictionary<string, int>(StringComparer.Ordinal);
            for (int k = 0; k < jk.Items.Count; ++k)
            {
                JsonValue key = jk.Items[k], w = key.Get("weights");
                if (key.Type != JsonType.Object) throw Bad(path, "keyframe " + k + " is not an object");
                if (w == null || w.Type != JsonType.Object)
                    throw Bad(path, "keyframe " + k + ": 'weights' is missing or not an object of name: weight");
                foreach (string n in w.Keys)
                    if (!slot.ContainsKey(n))
                    {
                        slot[n] = names.Count;
                        names.Add(n);
                    }
            }
            if (names.Count == 0) throw Bad(path, "no keyframe lists a weight");
            perf.Names = names.ToArray();
            int nn = names.Count;

            var times = new double[jk.Items.Count];
            var rows = new float[jk.Items.Count][];
            for (int k = 0; k < jk.Items.Count; ++k)
            {
                JsonValue key = jk.Items[k], t = key.Get("time"), w = key.Get("weights");
                if (t == null || t.Type != JsonType.Number || double.IsNaN(t.Number) || double.IsInfinity(t.Number))
                    throw Bad(path, "keyframe " + k + ": 'time' is missing or not a finite number");
                times[k] = t.Number;
                rows[k] = new float[nn];
                for (int m = 0; m < w.Keys.Count; ++m)
                {
                    double v = w.Items[m].Number;
                    if (w.Items[m].Type != JsonType.Number || !(v >= 0 && v <= 1))
                        throw Bad(path, "keyframe " + k + ": weight '" + w.Keys[m] + "' is not a number in [0, 1]");
                    rows[k][slot[w.Keys[m]]] = (float)v;  // a repeated name: the last one wins
                }
                if (k > 0 && !(times[k] > times[k - 1]))
                    throw Bad(path, "keyframe " + k + ": time " + times[k] + " is not after keyframe " + (k - 1) +
                                    "'s time " + times[k - 1]);
                if (key.Get("jaw") != null) perf.HasJaw = true;
            }

            int nk = times.Length;
            double span = (times[nk - 1] - times[0]) * perf.Fps;
            if (!(span < MaxFrames)) throw Bad(path, "the keyframes span more than " + MaxFrames + " frames");
            perf.Frames = (int)Math.Floor(span + 1e-6) + 1;
            perf.Weights = new float[perf.Frames * nn];
            for (int f = 0, k = 0; f < perf.Frames; ++f)
            {
                double t = times[0] + f / perf.Fps;
                if (t > times[nk - 1]) t = times[nk - 1];
                while (k + 1 < nk && times[k + 1] <= t) ++k;
                Sample(times, rows, k, t, perf.Weights, f * nn);
            }
            return perf;
        }

        // Weights at time t, with k the keyframe at or before it. Times within
        // rounding of a keyframe take it exactly, as the engine does.
        static void Sample(double[] times, float[][] rows, int k, double t, float[] out_, int at)
        {
            int n = rows[k].Length;
            if (k + 1 >= times.Length)
            {
                Array.Copy(rows[k], 0, out_, at, n);
                return;
            }
            double alpha = (t - times[k]) / (times[k + 1] - times[k]);
            if (alpha <= 1e-9)
                Array.Copy(rows[k], 0, out_, at, n);
            else if (alpha >= 1 - 1e-9)
                Array.Copy(rows[k + 1], 0, out_, at, n);
            else
                for (int i = 0; i < n; ++i)
                    out_[at + i] = (float)(rows[k][i] + alpha * ((double)rows[k + 1][i] - rows[k][i]));
        }
    }
}
