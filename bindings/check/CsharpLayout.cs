// CsharpLayout.exe: what the C# bindings (Facesr.dll) declare, in the
// consistency check's text format (see binding_check.cpp), found by
// reflection so that nothing here needs updating when the bindings grow:
//   struct <c name> size <Marshal.SizeOf>
//   field <c struct> <c field> offset <Marshal.OffsetOf> size <Marshal.SizeOf of its type>
//   const <FACESR_NAME> <value>
//   function <entry point> <param kinds|void> <return kind> <calling convention> <library>
// Only type metadata is read: the native library is never loaded.
using System;
using System.Collections.Generic;
using System.Reflection;
using System.Runtime.InteropServices;
using System.Text;

static class CsharpLayout
{
    // JawPivot -> jaw_pivot, NumLrNodes -> num_lr_nodes.
    static string Snake(string pascal)
    {
        var sb = new StringBuilder();
        for (int i = 0; i < pascal.Length; ++i)
        {
            char c = pascal[i];
            if (char.IsUpper(c) && i > 0 && (char.IsLower(pascal[i - 1]) || char.IsDigit(pascal[i - 1]))) sb.Append('_');
            sb.Append(char.ToLowerInvariant(c));
        }
        return sb.ToString();
    }

    static string NativeName(Type t)
    {
        foreach (var a in t.GetCustomAttributes(false))
        {
            var f = a.GetType().GetField("Name");
            if (a.GetType().Name == "NativeStructAttribute" && f != null) return (string)f.GetValue(a);
        }
        return null;
    }

    // The ABI kind of a parameter or return type, as binding_check names them.
    static string Kind(Type t)
    {
        if (t == typeof(void)) return "void";
        if (t.IsByRef || t.IsArray || t.IsPointer || t == typeof(IntPtr) || t == typeof(UIntPtr) ||
            t == typeof(string) || t == typeof(StringBuilder) || typeof(SafeHandle).IsAssignableFrom(t))
            return "ptr";
        if (t == typeof(int)) return "i32";
        if (t == typeof(uint)) return "u32";
        if (t == typeof(long)) return "i64";
        if (t == typeof(ulong)) return "u64";
        if (t == typeof(float)) return "f32";
        if (t == typeof(double)) return "f64";
        string n = NativeName(t);
        return n ?? "?" + t.FullName;
    }

    static int Main(string[] args)
    {
        if (args.Length != 1)
        {
            Console.Error.WriteLine("usage: CsharpLayout.exe Facesr.dll");
            return 2;
        }
        Assembly asm = Assembly.LoadFrom(args[0]);
        var lines = new List<string>();
        foreach (Type t in asm.GetTypes())
        {
            string cname = NativeName(t);
            if (cname != null)
            {
                lines.Add("struct " + cname + " size " + Marshal.SizeOf(t));
                foreach (FieldInfo f in t.GetFields(BindingFlags.Instance | BindingFlags.Public | BindingFlags.NonPublic))
                    lines.Add("field " + cname + " " + Snake(f.Name) + " offset " + Marshal.OffsetOf(t, f.Name) +
                              " size " + Marshal.SizeOf(f.FieldType));
            }
            foreach (FieldInfo f in t.GetFields(BindingFlags.Static | BindingFlags.Public | BindingFlags.NonPublic))
                if (f.IsLiteral && f.Name.StartsWith("FACESR_", StringComparison.Ordinal))
                    lines.Add("const " + f.Name + " " + Convert.ToInt64(f.GetRawConstantValue()));
            foreach (MethodInfo m in t.GetMethods(BindingFlags.Static | BindingFlags.Public | BindingFlags.NonPublic))
            {
                var dll = (DllImportAttribute)Attribute.GetCustomAttribute(m, typeof(DllImportAttribute));
                if (dll == null) continue;
                var kinds = new List<string>();
                foreach (ParameterInfo p in m.GetParameters()) kinds.Add(Kind(p.ParameterType));
                string entry = string.IsNullOrEmpty(dll.EntryPoint) ? m.Name : dll.EntryPoint;
                lines.Add("function " + entry + " " + (kinds.Count == 0 ? "void" : string.Join(",", kinds.ToArray())) +
                          " " + Kind(m.ReturnType) + " " + dll.CallingConvention + " " + dll.Value);
            }
        }
        lines.Sort(StringComparer.Ordinal);
        foreach (string l in lines) Console.WriteLine(l);
        return 0;
    }
}
