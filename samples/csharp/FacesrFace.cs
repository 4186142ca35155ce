// FacesrFace.cs: UNITY ONLY. A MonoBehaviour that steps a facesr face every
// frame and uploads its vertices to the GameObject's Mesh.
//
// Drop it into Assets/ next to the bindings (Assets/Plugins/Facesr/*.cs) and
// the native library (see README.md), put the rig and model files in
// Assets/StreamingAssets/, and add the component to a GameObject with a
// MeshFilter and a MeshRenderer.
//
// It is not part of the sample program. CI compiles it against a tiny stub
// of the few UnityEngine types it uses (unity_stub/UnityEngine.cs) only to
// keep it compiling; it is not run there.
//
// Coordinates: facesr is right-handed, +y up, +z out of the face, in cm.
// Unity is left-handed, +y up, in metres. Each vertex becomes
// (x, y, -z) * 0.01, and because mirroring z reverses the apparent winding,
// the triangles are reversed once at start. The face then looks toward -z,
// at a default camera.
//
// Per frame nothing is allocated on the managed heap: the float buffers and
// Vector3 arrays are made once, and the Facesr calls allocate nothing.
using System;
using System.IO;
using Facesr;
using UnityEngine;

[RequireComponent(typeof(MeshFilter))]
public sealed class FacesrFace : MonoBehaviour
{
    [Tooltip("Rig file, relative to Assets/StreamingAssets")]
    public string rigFile = "face.rig";

    [Tooltip("Super-resolution model file, relative to Assets/StreamingAssets")]
    public string modelFile = "face.fsm";

    [Tooltip("Overlap simulation and super-resolution (shows each frame one Update late)")]
    public bool pipelined = true;

    [Tooltip("CPU reference inference instead of OpenCL (slow; for checks)")]
    public bool cpuInference = false;

    [Range(0, 1)] public float jawOpen;
    [Range(0, 1)] public float mouthSmileLeft;
    [Range(0, 1)] public float mouthSmileRight;

    Rig rig;
    Model model;
    Context face;
    Mesh mesh;
    float[] xyz, nrm;          // facesr's layout: x, y, z per vertex (cm)
    Vector3[] vertices, normals;
    int jawOpenIndex = -1, smileLeftIndex = -1, smileRightIndex = -1;

    void Start()
    {
        try
        {
            FacesrLibrary.EnsureCompatible();
            rig = Rig.Load(Path.Combine(Application.streamingAssetsPath, rigFile));
            model = Model.Load(Path.Combine(Application.streamingAssetsPath, modelFile));
            face = new Context(rig, model, new ContextOptions { Inference = cpuInference ? Inference.Cpu : Inference.OpenCL });
        }
        catch (Exception e)  // FacesrException (status + engine message), DllNotFoundException, ...
        {
            Debug.LogError("FacesrFace: " + e.Message);
            enabled = false;
            return;
        }
        // Indices once, so Update sets weights without name lookups.
        rig.TryGetBlendshapeIndex("jawOpen", out jawOpenIndex);
        rig.TryGetBlendshapeIndex("mouthSmile_L", out smileLeftIndex);
        rig.TryGetBlendshapeIndex("mouthSmile_R", out smileRightIndex);

        xyz = new float[rig.PositionFloats];
        nrm = new float[rig.PositionFloats];
        vertices = new Vector3[rig.VertexCount];
        normals = new Vector3[rig.VertexCount];

        int[] triangles = rig.GetTriangles();
        for (int t = 0; t < triangles.Length; t += 3)
        {
            int b = triangles[t + 1];
            triangles[t + 1] = triangles[t + 2];
            triangles[t + 2] = b;
        }
        mesh = new Mesh();
        mesh.name = "facesr face";
        if (rig.VertexCount > 65535) mesh.indexFormat = UnityEngine.Rendering.IndexFormat.UInt32;
        mesh.MarkDynamic();  // rewritten every frame
        face.GetPositions(xyz);  // before the first step: the rest pose
        face.GetNormals(nrm);
        Upload();
        mesh.triangles = triangles;
        mesh.RecalculateBounds();
        GetComponent<MeshFilter>().sharedMesh = mesh;
    }

    void Update()
    {
        try
        {
            if (jawOpenIndex >= 0) face.SetWeight(jawOpenIndex, jawOpen);
            if (smileLeftIndex >= 0) face.SetWeight(smileLeftIndex, mouthSmileLeft);
            if (smileRightIndex >= 0) face.SetWeight(smileRightIndex, mouthSmileRight);
            if (!pipelined)
            {
                face.Step();
            }
            else
            {
                face.StepAsync();  // this frame runs while the previous one is shown
                if (face.PendingFrames < 2) return;
                face.Wait();
            }
            face.GetPositions(xyz);
            face.GetNormals(nrm);
        }
        catch (FacesrException e)  // the face keeps its last good frame
        {
            Debug.LogError("FacesrFace: " + e.Message);
            enabled = false;
            return;
        }
        Upload();
    }

    // facesr (right-handed, cm) to Unity (left-handed, m).
    void Upload()
    {
        for (int v = 0, i = 0; v < vertices.Length; ++v, i += 3)
        {
            vertices[v] = new Vector3(0.01f * xyz[i], 0.01f * xyz[i + 1], -0.01f * xyz[i + 2]);
            normals[v] = new Vector3(nrm[i], nrm[i + 1], -nrm[i + 2]);
        }
        mesh.vertices = vertices;
        mesh.normals = normals;
    }

    void OnDestroy()
    {
        // The context first (it waits for frames in flight), then what it used.
        if (face != null) face.Dispose();
        if (model != null) model.Dispose();
        if (rig != null) rig.Dispose();
        if (mesh != null) Destroy(mesh);
    }
}
