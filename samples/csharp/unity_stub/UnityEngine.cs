// A stub of the few UnityEngine types FacesrFace.cs uses, with the same
// names and signatures as Unity's, so that CI can keep FacesrFace.cs
// compiling without Unity. Nothing here does anything; it is never run and
// must never be copied into a Unity project (Unity provides the real ones).
using System;

namespace UnityEngine
{
    public class Object
    {
        public string name;
        public static void Destroy(Object obj) { }
    }

    public class Component : Object
    {
        public T GetComponent<T>() { return default(T); }
    }

    public class Behaviour : Component
    {
        public bool enabled;
    }

    public class MonoBehaviour : Behaviour { }

    public sealed class MeshFilter : Component
    {
        public Mesh sharedMesh;
    }

    public sealed class Mesh : Object
    {
        public Rendering.IndexFormat indexFormat;
        public Vector3[] vertices;
        public Vector3[] normals;
        public int[] triangles;
        public void MarkDynamic() { }
        public void RecalculateBounds() { }
    }

    public struct Vector3
    {
        public float x, y, z;
        public Vector3(float x, float y, float z) { this.x = x; this.y = y; this.z = z; }
    }

    public static class Debug
    {
        public static void LogError(object message) { }
    }

    public static class Application
    {
        public static string streamingAssetsPath { get { return ""; } }
    }

    [AttributeUsage(AttributeTargets.Class, AllowMultiple = true)]
    public sealed class RequireComponent : Attribute
    {
        public RequireComponent(Type type) { }
    }

    [AttributeUsage(AttributeTargets.Field)]
    public sealed class TooltipAttribute : Attribute
    {
        public TooltipAttribute(string tooltip) { }
    }

    [AttributeUsage(AttributeTargets.Field)]
    public sealed class RangeAttribute : Attribute
    {
        public RangeAttribute(float min, float max) { }
    }
}

namespace UnityEngine.Rendering
{
    public enum IndexFormat { UInt16, UInt32 }
}
