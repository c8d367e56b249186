// The C ABI (facerig.h, facerig_tts.h) declared for P/Invoke, as Unity and
// Godot-Mono load native plugins: DllImport by library name ("facerig" finds
// libfacerig.so on Linux, facerig.dll on Windows), handles as SafeHandles so
// that the runtime releases them even when the caller forgets.
using System;
using System.Runtime.InteropServices;

namespace Facerig
{
    public enum Status
    {
        Ok = 0, InvalidArgument = 1, BufferTooSmall = 2, NotFound = 3, File = 4, Format = 5,
        Speech = 6, State = 7, Limit = 8, OutOfMemory = 9, Internal = 10
    }

    public enum NormalMode { None = 0, BlendDeltas = 1, Recompute = 2 }

    public enum Emotion { Joy = 0, Sadness = 1, Fear = 2, Anger = 3, Surprise = 4, Disgust = 5 }

    [StructLayout(LayoutKind.Sequential)]
    public struct RigInfo
    {
        public uint VertexCount, TriangleCount, ShapeCount, PartCount, HasUvs, HasNormalDeltas, Units, UpAxis;
        public float BoundingDiagonal;
    }

    [StructLayout(LayoutKind.Sequential)]
    public struct PartInfo
    {
        public uint FirstTriangle, TriangleCount, FirstVertex, VertexCount;
        public int Material;
    }

    [StructLayout(LayoutKind.Sequential)]
    internal struct NativePhoneme
    {
        public double Start, Duration;
        [MarshalAs(UnmanagedType.ByValArray, SizeConst = 16)] public byte[] Symbol;
        [MarshalAs(UnmanagedType.ByValArray, SizeConst = 16)] public byte[] Language;
        public int WordStart, Reserved;
    }

    [StructLayout(LayoutKind.Sequential)]
    public struct CharacterOptions
    {
        public ulong Seed;
        public float JawIntensity, LipIntensity;
        public uint KeyCapacity, Blinks, Gaze;
    }

    [StructLayout(LayoutKind.Sequential)]
    internal struct NativeCharacterState
    {
        public int Talking, AtPause, Viseme;
        public float BlinkLeft, BlinkRight, GazeX, GazeY;
        [MarshalAs(UnmanagedType.ByValArray, SizeConst = 16)] public byte[] Phoneme;
    }

    public abstract class FacerigHandle : SafeHandle
    {
        protected FacerigHandle() : base(IntPtr.Zero, true) { }
        public override bool IsInvalid { get { return handle == IntPtr.Zero; } }
    }

    public sealed class RigHandle : FacerigHandle
    {
        protected override bool ReleaseHandle() { Native.fr_rig_release(handle); return true; }
    }

    public sealed class SpeechHandle : FacerigHandle
    {
        protected override bool ReleaseHandle() { Native.fr_speech_release(handle); return true; }
    }

    public sealed class CharacterHandle : FacerigHandle
    {
        protected override bool ReleaseHandle() { Native.fr_character_release(handle); return true; }
    }

    internal static class Native
    {
        const string Lib = "facerig";
        const string Tts = "facerig_espeak";

        [DllImport(Lib)] public static extern uint fr_abi_version();
        [DllImport(Lib)] public static extern IntPtr fr_last_error();
        [DllImport(Lib)] public static extern Status fr_rig_load_file(string path, out RigHandle rig);
        [DllImport(Lib)] public static extern Status fr_rig_load_bytes(byte[] bytes, UIntPtr size, string name, out RigHandle rig);
        [DllImport(Lib)] public static extern void fr_rig_release(IntPtr rig);
        [DllImport(Lib)] public static extern Status fr_rig_get_info(RigHandle rig, out RigInfo info);
        [DllImport(Lib)] public static extern Status fr_rig_shape_name(RigHandle rig, uint index, byte[] buffer, UIntPtr capacity, out UIntPtr needed);
        [DllImport(Lib)] public static extern Status fr_rig_find_shape(RigHandle rig, string name, out uint index);
        [DllImport(Lib)] public static extern Status fr_rig_part_info(RigHandle rig, uint index, out PartInfo info);
        [DllImport(Lib)] public static extern Status fr_rig_neutral(RigHandle rig, float[] positions, float[] normals, UIntPtr capacity, IntPtr needed);
        [DllImport(Lib)] public static extern Status fr_rig_blend(RigHandle rig, float[] weights, UIntPtr weightCount, NormalMode mode, float[] positions, float[] normals, UIntPtr vertexCapacity);
        [DllImport(Lib)] public static extern Status fr_speech_load_track_file(string path, out SpeechHandle speech);
        [DllImport(Lib)] public static extern Status fr_speech_load_track_bytes(byte[] json, UIntPtr size, out SpeechHandle speech);
        [DllImport(Lib)] public static extern Status fr_speech_from_audio(float[] samples, UIntPtr count, int sampleRate, out SpeechHandle speech);
        [DllImport(Lib)] public static extern void fr_speech_release(IntPtr speech);
        [DllImport(Lib)] public static extern Status fr_speech_phonemes(SpeechHandle speech, [Out] NativePhoneme[] phonemes, UIntPtr capacity, out UIntPtr needed);
        [DllImport(Lib)] public static extern Status fr_character_default_options(out CharacterOptions options);
        [DllImport(Lib)] public static extern Status fr_character_create(RigHandle rig, ref CharacterOptions options, out CharacterHandle character);
        [DllImport(Lib)] public static extern void fr_character_release(IntPtr character);
        [DllImport(Lib)] public static extern Status fr_character_speak(CharacterHandle character, SpeechHandle speech, double startTime);
        [DllImport(Lib)] public static extern Status fr_character_begin_line(CharacterHandle character, double startTime);
        [DllImport(Lib)] public static extern Status fr_character_push_phoneme(CharacterHandle character, ref NativePhoneme phoneme);
        [DllImport(Lib)] public static extern Status fr_character_end_line(CharacterHandle character);
        [DllImport(Lib)] public static extern Status fr_character_stop(CharacterHandle character);
        [DllImport(Lib)] public static extern Status fr_character_set_emotion(CharacterHandle character, Emotion emotion, float target);
        [DllImport(Lib)] public static extern Status fr_character_set_behaviour(CharacterHandle character, int blinks, int gaze);
        [DllImport(Lib)] public static extern Status fr_character_update(CharacterHandle character, double time, float[] weights, UIntPtr capacity);
        [DllImport(Lib)] public static extern Status fr_character_get_state(CharacterHandle character, out NativeCharacterState state);
        [DllImport(Tts)] public static extern Status fr_tts_synthesize(string text, string voice, out SpeechHandle speech);
    }
}
