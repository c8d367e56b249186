// The C# binding under Mono: load the built-in head, speak a phoneme track and
// a synthesised line at 60 fps, read the weights, blend, check that the lips
// close on every p/b/m; wrong calls throw with the ABI's status and message;
// disposed objects throw ObjectDisposedException. Exit code 0 when all pass.
using System;
using System.IO;
using Facerig;

static class FacerigTest
{
    static int failures = 0;

    static void Check(bool condition, string what)
    {
        if (condition) return;
        Console.Error.WriteLine("FAILED: " + what);
        ++failures;
    }

    static void Throws(Status expected, string messagePart, Action action, string what)
    {
        try
        {
            action();
            Check(false, what + ": no exception");
        }
        catch (FacerigException e)
        {
            Check(e.Status == expected, what + ": status " + e.Status + " (" + e.Message + ")");
            Check(e.Message.Contains(messagePart), what + ": message \"" + e.Message + "\" lacks \"" + messagePart + "\"");
        }
    }

    const string Track = "{\"version\": 1, \"language\": \"en-us\", \"phonemes\": [" +
        "{\"start\": 0.00, \"duration\": 0.10, \"symbol\": \"_:\"}, {\"start\": 0.10, \"duration\": 0.12, \"symbol\": \"a#\"}," +
        "{\"start\": 0.22, \"duration\": 0.04, \"symbol\": \"p\"}, {\"start\": 0.26, \"duration\": 0.12, \"symbol\": \"A:\"}," +
        "{\"start\": 0.38, \"duration\": 0.03, \"symbol\": \"b\"}, {\"start\": 0.41, \"duration\": 0.12, \"symbol\": \"A:\"}," +
        "{\"start\": 0.53, \"duration\": 0.05, \"symbol\": \"m\"}, {\"start\": 0.58, \"duration\": 0.15, \"symbol\": \"A:\"}," +
        "{\"start\": 0.73, \"duration\": 0.20, \"symbol\": \"_:\"}]}";

    static float Distance(float[] p, uint a, uint b)
    {
        float dx = p[3 * a] - p[3 * b], dy = p[3 * a + 1] - p[3 * b + 1], dz = p[3 * a + 2] - p[3 * b + 2];
        return (float)Math.Sqrt(dx * dx + dy * dy + dz * dz);
    }

    // The inner-lip contact on the midline, as hosts/c/tests/consumer.c finds it.
    static uint[] FindLips(Rig rig, float[] neutral)
    {
        uint n = rig.Info.VertexCount;
        float[] weights = new float[rig.Info.ShapeCount], open = new float[3 * n], moved = new float[n];
        weights[rig.FindShape("jawOpen")] = 1.0f;
        rig.Blend(weights, open);
        float most = 0;
        for (uint i = 0; i < n; ++i) { moved[i] = Distance2(open, neutral, i); most = Math.Max(most, moved[i]); }
        PartInfo skin = rig.Part(0);
        float limit = 0.01f * rig.Info.BoundingDiagonal, best = float.MaxValue;
        uint[] lips = new uint[2];
        for (uint i = skin.FirstVertex; i < skin.FirstVertex + skin.VertexCount; ++i)
        {
            if (Math.Abs(neutral[3 * i]) > limit || moved[i] < 0.5f * most) continue;
            for (uint j = skin.FirstVertex; j < skin.FirstVertex + skin.VertexCount; ++j)
            {
                if (Math.Abs(neutral[3 * j]) > limit || moved[j] > 0.1f * most) continue;
                float d = Distance(neutral, i, j);
                if (d < best) { best = d; lips[0] = j; lips[1] = i; }
            }
        }
        return lips;
    }

    static float Distance2(float[] a, float[] b, uint i)
    {
        float dx = a[3 * i] - b[3 * i], dy = a[3 * i + 1] - b[3 * i + 1], dz = a[3 * i + 2] - b[3 * i + 2];
        return (float)Math.Sqrt(dx * dx + dy * dy + dz * dz);
    }

    // Speaks at 60 fps; returns how many bilabials closed the lips (each must).
    static int SpeakAndCountClosures(Rig rig, Speech speech, uint[] lips, double seconds)
    {
        Phoneme[] phonemes = speech.Phonemes();
        int frames = (int)(seconds * 60);
        float[] weights = new float[rig.Info.ShapeCount], positions = new float[3 * rig.Info.VertexCount];
        float[] aperture = new float[frames];
        float widest = 0;
        bool sawPP = false;
        using (Character character = new Character(rig))
        {
            character.Speak(speech, 0.0);
            for (int f = 0; f < frames; ++f)
            {
                character.Update(f / 60.0, weights);
                rig.Blend(weights, positions);
                aperture[f] = Distance(positions, lips[0], lips[1]);
                widest = Math.Max(widest, aperture[f]);
                sawPP = sawPP || character.Viseme == 1;
            }
        }
        Check(widest > 0.5f, "the mouth opens (" + widest + " cm)");
        Check(sawPP, "the PP viseme shows");
        int closures = 0;
        foreach (Phoneme p in phonemes)
        {
            if (p.Symbol != "p" && p.Symbol != "b" && p.Symbol != "m") continue;
            float lowest = float.MaxValue;
            for (int f = 0; f < frames; ++f)
            {
                double t = f / 60.0;
                if (t >= p.Start - 0.06 && t <= p.Start + Math.Max(p.Duration, 0.03)) lowest = Math.Min(lowest, aperture[f]);
            }
            Check(lowest < 0.1f * widest, p.Symbol + " at " + p.Start + " s closes the lips (" + lowest + " of " + widest + ")");
            ++closures;
        }
        return closures;
    }

    static int Main(string[] args)
    {
        string head = args[0];
        using (Rig rig = Rig.Load(head))
        {
            Console.WriteLine(head + ": " + rig.Info.VertexCount + " vertices, " + rig.Info.ShapeCount + " shapes, first " + rig.ShapeName(0));
            uint[] lips = FindLips(rig, rig.NeutralPositions());
            using (Speech track = Speech.FromTrack(Track))
            {
                Check(SpeakAndCountClosures(rig, track, lips, 1.0) == 3, "the track's three bilabials");
            }
            using (Speech line = Speech.Synthesize("Bob bought a map from a puppet maker.", "en-us"))
            {
                int closures = SpeakAndCountClosures(rig, line, lips, 3.0);
                Console.WriteLine("synthesised line: " + closures + " bilabials, each closing the lips");
                Check(closures >= 5, "the line's bilabials");
            }

            // Per frame through P/Invoke: float[] pinned, not copied; nothing allocated once warm.
            using (Speech track = Speech.FromTrack(Track))
            using (Character talker = new Character(rig))
            {
                talker.Speak(track, 0.0);
                float[] weights = new float[rig.Info.ShapeCount], positions = new float[3 * rig.Info.VertexCount];
                for (int f = 0; f < 10; ++f) { talker.Update(f / 60.0, weights); rig.Blend(weights, positions); }
                long before = GC.GetAllocatedBytesForCurrentThread();
                for (int f = 10; f < 610; ++f) { talker.Update(f / 60.0, weights); rig.Blend(weights, positions); }
                long allocated = GC.GetAllocatedBytesForCurrentThread() - before;
                Console.WriteLine("600 frames of Update + Blend: " + allocated + " bytes allocated");
                Check(allocated == 0, "per-frame calls allocate nothing (" + allocated + " bytes)");
            }

            Throws(Status.File, "no_such_head.glb", () => Rig.Load("/nonexistent/no_such_head.glb"), "missing file");
            byte[] glb = File.ReadAllBytes(Path.ChangeExtension(head, ".glb"));
            Array.Resize(ref glb, glb.Length / 2);
            Throws(Status.Format, "half.glb", () => Rig.FromBytes(glb, "half.glb"), "truncated GLB");
            Throws(Status.BufferTooSmall, "need room for", () => rig.Blend(new float[rig.Info.ShapeCount], new float[30]), "small buffer");
            Throws(Status.InvalidArgument, "weight_count", () => rig.Blend(new float[3], new float[30]), "wrong weight count");
            Throws(Status.NotFound, "noSuchShape", () => rig.FindShape("noSuchShape"), "unknown shape");
            Character character = new Character(rig);
            Phoneme p = new Phoneme();
            p.Symbol = "p";
            Throws(Status.State, "BeginLine", () => character.PushPhoneme(p), "push without a line");
            Throws(Status.BufferTooSmall, "weights", () => character.Update(0.0, new float[3]), "small weights");
            character.Dispose();
            try
            {
                character.Update(0.0, new float[rig.Info.ShapeCount]);
                Check(false, "a disposed character throws");
            }
            catch (ObjectDisposedException) { }
        }
        if (failures > 0) Console.Error.WriteLine(failures + " checks failed");
        else Console.WriteLine("all checks passed");
        return failures == 0 ? 0 : 1;
    }
}
