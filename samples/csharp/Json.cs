// Json.cs: a small strict JSON reader (RFC 8259), enough for a performance
// file: the same grammar the C sample's json.c accepts, nesting bounded so
// that a hostile file cannot exhaust the stack.
using System;
using System.Collections.Generic;
using System.Globalization;
using System.Text;

namespace FacesrSample
{
    enum JsonType { Null, Bool, Number, String, Array, Object }

    sealed class JsonValue
    {
        public JsonType Type;
        public bool Bool;
        public double Number;
        public string String;
        public readonly List<JsonValue> Items = new List<JsonValue>();  // array elements, object values
        public readonly List<string> Keys = new List<string>();         // object member names, parallel to Items

        // The member `key` of an object (the last one if repeated), or null.
        public JsonValue Get(string key)
        {
            if (Type != JsonType.Object) return null;
            for (int i = Keys.Count - 1; i >= 0; --i)
                if (Keys[i] == key) return Items[i];
            return null;
        }
    }

    sealed class JsonException : Exception
    {
        public JsonException(string message) : base(message) { }
    }

    sealed class JsonParser
    {
        const int MaxDepth = 64;
        readonly string text;
        int p;

        JsonParser(string text) { this.text = text; }

        // Parses a whole document; JsonException "line L, column C: problem".
        public static JsonValue Parse(string text)
        {
            var ps = new JsonParser(text);
            if (text.Length > 0 && text[0] == '\uFEFF') ps.p = 1;  // byte order mark
            JsonValue v = ps.Value(0);
            ps.SkipSpace();
            if (ps.p != text.Length) ps.Fail("unexpected text after the JSON value");
            return v;
        }

        void Fail(string what)
        {
            int line = 1, column = 1;
            for (int i = 0; i < p && i < text.Length; ++i)
            {
                if (text[i] == '\n')
                {
                    ++line;
                    column = 1;
                }
                else
                {
                    ++column;
                }
            }
            throw new JsonException("line " + line + ", column " + column + ": " + what);
        }

        void SkipSpace()
        {
            while (p < text.Length && (text[p] == ' ' || text[p] == '\t' || text[p] == '\n' || text[p] == '\r')) ++p;
        }

        bool Literal(string word)
        {
            if (string.CompareOrdinal(text, p, word, 0, word.Length) != 0) return false;
            p += word.Length;
            return true;
        }

        JsonValue Value(int depth)
        {
            SkipSpace();
            if (p >= text.Length) Fail("unexpected end of input");
            var v = new JsonValue();
            char c = text[p];
            if (c == '{' || c == '[')
            {
                ++p;
                Container(v, depth, c == '{' ? '}' : ']');
            }
            else if (c == '"')
            {
                ++p;
                v.Type = JsonType.String;
                v.String = StringBody();
            }
            else if (c == 't' && Literal("true"))
            {
                v.Type = JsonType.Bool;
                v.Bool = true;
            }
            else if (c == 'f' && Literal("false"))
            {
                v.Type = JsonType.Bool;
            }
            else if (c == 'n' && Literal("null"))
            {
                v.Type = JsonType.Null;
            }
            else if (!NumberBody(v))
            {
                Fail("expected a JSON value");
            }
            return v;
        }

        void Container(JsonValue v, int depth, char close)
        {
            v.Type = close == '}' ? JsonType.Object : JsonType.Array;
            if (depth >= MaxDepth) Fail("nested too deeply");
            SkipSpace();
            if (p < text.Length && text[p] == close)
            {
                ++p;
                return;
            }
            for (;;)
            {
                SkipSpace();
                if (v.Type == JsonType.Object)
                {
                    if (p >= text.Length || text[p] != '"') Fail("expected a member name in quotes");
                    ++p;
                    v.Keys.Add(StringBody());
                    SkipSpace();
                    if (p >= text.Length || text[p] != ':') Fail("expected ':' after a member name");
                    ++p;
                }
                v.Items.Add(Value(depth + 1));
                SkipSpace();
                if (p < text.Length && text[p] == ',')
                {
                    ++p;
                    continue;
                }
                if (p < text.Length && text[p] == close)
                {
                    ++p;
                    return;
                }
                Fail(close == '}' ? "expected ',' or '}'" : "expected ',' or ']'");
            }
        }

        int Hex4()
        {
            if (text.Length - p < 4) Fail("bad \\u escape");
            int v = 0;
            for (int i = 0; i < 4; ++i)
            {
                char c = text[p++];
                int d = c >= '0' && c <= '9' ? c - '0' : c >= 'a' && c <= 'f' ? c - 'a' + 10
                      : c >= 'A' && c <= 'F' ? c - 'A' + 10 : -1;
                if (d < 0) Fail("bad \\u escape");
                v = v * 16 + d;
            }
            return v;
        }

        // After the opening quote.
        string StringBody()
        {
            var sb = new StringBuilder();
            for (;;)
            {
                if (p >= text.Length) Fail("unterminated string");
                char c = text[p++];
                if (c == '"') return sb.ToString();
                if (c < 0x20) Fail("control character in a string");
                if (c != '\\')
                {
                    sb.Append(c);
                    continue;
                }
                if (p >= text.Length) Fail("unterminated escape");
                c = text[p++];
                switch (c)
                {
                    case '"': case '\\': case '/': sb.Append(c); break;
                    case 'b': sb.Append('\b'); break;
                    case 'f': sb.Append('\f'); break;
                    case 'n': sb.Append('\n'); break;
                    case 'r': sb.Append('\r'); break;
                    case 't': sb.Append('\t'); break;
                    case 'u':
                    {
                        int cp = Hex4();
                        if (cp >= 0xD800 && cp <= 0xDBFF)
                        {
                            if (!Literal("\\u")) Fail("unpaired UTF-16 surrogate in a \\u escape");
                            int low = Hex4();
                            if (low < 0xDC00 || low > 0xDFFF) Fail("unpaired UTF-16 surrogate in a \\u escape");
                            sb.Append((char)cp).Append((char)low);
                        }
                        else if (cp >= 0xDC00 && cp <= 0xDFFF)
                        {
                            Fail("unpaired UTF-16 surrogate in a \\u escape");
                        }
                        else
                        {
                            sb.Append((char)cp);
                        }
                        break;
                    }
                    default: Fail("unknown escape in a string"); break;
                }
            }
        }

        // The JSON number grammar, checked by hand (double.Parse alone would
        // take "Infinity", "1,5" or leading '+').
        bool NumberBody(JsonValue v)
        {
            int q = p;
            if (q < text.Length && text[q] == '-') ++q;
            if (q < text.Length && text[q] == '0')
                ++q;
            else if (q < text.Length && text[q] >= '1' && text[q] <= '9')
                while (q < text.Length && text[q] >= '0' && text[q] <= '9') ++q;
            else
                return false;
            if (q < text.Length && text[q] == '.')
            {
                ++q;
                if (q >= text.Length || text[q] < '0' || text[q] > '9') return false;
                while (q < text.Length && text[q] >= '0' && text[q] <= '9') ++q;
            }
            if (q < text.Length && (text[q] == 'e' || text[q] == 'E'))
            {
                ++q;
                if (q < text.Length && (text[q] == '+' || text[q] == '-')) ++q;
                if (q >= text.Length || text[q] < '0' || text[q] > '9') return false;
                while (q < text.Length && text[q] >= '0' && text[q] <= '9') ++q;
            }
            if (q - p >= 64) return false;  // no real weight or time needs 64 digits (as json.c)
            v.Type = JsonType.Number;
            string digits = text.Substring(p, q - p);
            try
            {
                v.Number = double.Parse(digits, NumberStyles.Float, CultureInfo.InvariantCulture);
            }
            catch (OverflowException)  // .NET Framework; strtod gives +-HUGE_VAL
            {
                v.Number = digits[0] == '-' ? double.NegativeInfinity : double.PositiveInfinity;
            }
            p = q;
            return true;
        }
    }
}
