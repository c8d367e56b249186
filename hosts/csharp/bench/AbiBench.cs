// Per-frame cost through the C# binding under Mono, for `facerig-bench abi`.
// AbiBench.exe HEAD TRACK FRAMES REPEATS: a character speaks TRACK on HEAD;
// FRAMES frames of Character.Update (and of Update + Rig.Blend) into arrays
// made once, the best of REPEATS runs; prints {"update_us": .., "update_blend_us": ..}.
using System;
using System.Diagnostics;
using System.Globalization;
using System.IO;
using Facerig;

static class AbiBench
{
    static double BestPerFrame(int frames, int repeats, Action<int> frame)
    {
        double best = double.MaxValue;
        for (int r = 0; r < repeats; ++r)
        {
            Stopwatch watch = Stopwatch.StartNew();
            for (int i = 0; i < frames; ++i) frame(i);
            best = Math.Min(best, watch.Elapsed.TotalMilliseconds * 1000.0 / frames);
        }
        return best;
    }

    static int Main(string[] args)
    {
        int frames = int.Parse(args[2]), repeats = int.Parse(args[3]);
        const int period = 840;  // 14 s of frames, the track's length
        using (Rig rig = Rig.Load(args[0]))
        using (Speech speech = Speech.FromTrack(File.ReadAllText(args[1])))
        using (Character character = new Character(rig))
        {
            character.Speak(speech, 0.0);
            float[] weights = new float[rig.Info.ShapeCount], positions = new float[3 * rig.Info.VertexCount];
            double update = BestPerFrame(frames, repeats, i => character.Update((i % period) / 60.0, weights));
            double updateBlend = BestPerFrame(Math.Max(frames / 10, 1), repeats, i =>
            {
                character.Update((i % period) / 60.0, weights);
                rig.Blend(weights, positions);
            });
            Console.WriteLine(string.Format(CultureInfo.InvariantCulture,
                                            "{{\"update_us\": {0}, \"update_blend_us\": {1}}}", update, updateBlend));
        }
        return 0;
    }
}
