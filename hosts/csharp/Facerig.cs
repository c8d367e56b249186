// facerig for C# (Unity, Godot-Mono, .NET on Mono): Rig, Speech and Character
// over the C ABI. Every failed call throws a FacerigException carrying the
// ABI's status and message; a disposed object throws ObjectDisposedException.
// Per frame, Character.Update and Rig.Blend write into arrays you own and
// allocate nothing (float[] is pinned for the call, not copied).
using System;
using System.Runtime.InteropServices;
using System.Text;

namespace Facerig
{
    public class FacerigException : Exception
    {
        public Status Status { get; private set; }
        public FacerigException(Status status, string message) : base(message) { Status = status; }

        internal static void Check(Status status)
        {
            if (status != Status.Ok) throw new FacerigException(status, LastError());
        }

        internal static string LastError()
        {
            return Utf8(Native.fr_last_error());
        }

        internal static string Utf8(IntPtr text)
        {
            int length = 0;
            while (Marshal.ReadByte(text, length) != 0) ++length;
            byte[] bytes = new byte[length];
            Marshal.Copy(text, bytes, 0, length);
            return Encoding.UTF8.GetString(bytes);
        }
    }

    public struct Phoneme
    {
        public double Start, Duration;
        public string Symbol, Language;
        public bool WordStart;

        internal NativePhoneme ToNative()
        {
            NativePhoneme p = new NativePhoneme();
            p.Start = Start; p.Duration = Duration;
            p.Symbol = Name(Symbol); p.Language = Name(Language);
            p.WordStart = WordStart ? 1 : 0;
            return p;
        }

        internal static Phoneme FromNative(NativePhoneme p)
        {
            Phoneme result = new Phoneme();
            result.Start = p.Start; result.Duration = p.Duration;
            result.Symbol = Text(p.Symbol); result.Language = Text(p.Language);
            result.WordStart = p.WordStart != 0;
            return result;
        }

        static byte[] Name(string text)
        {
            byte[] name = new byte[16];
            byte[] bytes = Encoding.UTF8.GetBytes(text ?? "");
            Array.Copy(bytes, name, Math.Min(bytes.Length, 15));
            return name;
        }

        static string Text(byte[] name)
        {
            int length = Array.IndexOf(name, (byte)0);
            return Encoding.UTF8.GetString(name, 0, length < 0 ? name.Length : length);
        }
    }

    /// <summary>A loaded rig: neutral mesh plus named blend shapes. Immutable; characters keep it alive.</summary>
    public sealed class Rig : IDisposable
    {
        internal readonly RigHandle Handle;
        public RigInfo Info { get; private set; }

        Rig(RigHandle handle)
        {
            Handle = handle;
            RigInfo info;
            FacerigException.Check(Native.fr_rig_get_info(Handle, out info));
            Info = info;
        }

        /// <summary>Loads a .glb, .gltf, .frig or .obj file.</summary>
        public static Rig Load(string path)
        {
            RigHandle handle;
            FacerigException.Check(Native.fr_rig_load_file(path, out handle));
            return new Rig(handle);
        }

        /// <summary>Loads the bytes of a .glb or .frig (name only for messages).</summary>
        public static Rig FromBytes(byte[] bytes, string name)
        {
            RigHandle handle;
            FacerigException.Check(Native.fr_rig_load_bytes(bytes, (UIntPtr)bytes.Length, name, out handle));
            return new Rig(handle);
        }

        public string ShapeName(uint index)
        {
            UIntPtr needed;
            byte[] buffer = new byte[64];
            Status status = Native.fr_rig_shape_name(Handle, index, buffer, (UIntPtr)buffer.Length, out needed);
            if (status == Status.BufferTooSmall)
            {
                buffer = new byte[(int)needed];
                status = Native.fr_rig_shape_name(Handle, index, buffer, (UIntPtr)buffer.Length, out needed);
            }
            FacerigException.Check(status);
            return Encoding.UTF8.GetString(buffer, 0, (int)needed - 1);
        }

        public uint FindShape(string name)
        {
            uint index;
            FacerigException.Check(Native.fr_rig_find_shape(Handle, name, out index));
            return index;
        }

        public PartInfo Part(uint index)
        {
            PartInfo info;
            FacerigException.Check(Native.fr_rig_part_info(Handle, index, out info));
            return info;
        }

        /// <summary>Neutral positions, 3 floats per vertex.</summary>
        public float[] NeutralPositions()
        {
            float[] positions = new float[3 * Info.VertexCount];
            FacerigException.Check(Native.fr_rig_neutral(Handle, positions, null, (UIntPtr)Info.VertexCount, IntPtr.Zero));
            return positions;
        }

        /// <summary>Per frame: positions (3 floats per vertex) for one weight per shape. Allocates nothing.</summary>
        public void Blend(float[] weights, float[] positions)
        {
            FacerigException.Check(Native.fr_rig_blend(Handle, weights, (UIntPtr)weights.Length, NormalMode.None,
                                                       positions, null, (UIntPtr)(positions.Length / 3)));
        }

        public void Dispose() { Handle.Dispose(); }
    }

    /// <summary>A line to speak: timed phonemes and optional audio. Immutable.</summary>
    public sealed class Speech : IDisposable
    {
        internal readonly SpeechHandle Handle;
        Speech(SpeechHandle handle) { Handle = handle; }

        /// <summary>A phoneme-track file (JSON, facerig-phoneme-track version 1).</summary>
        public static Speech FromTrackFile(string path)
        {
            SpeechHandle handle;
            FacerigException.Check(Native.fr_speech_load_track_file(path, out handle));
            return new Speech(handle);
        }

        /// <summary>A phoneme track's JSON text.</summary>
        public static Speech FromTrack(string json)
        {
            byte[] bytes = Encoding.UTF8.GetBytes(json);
            SpeechHandle handle;
            FacerigException.Check(Native.fr_speech_load_track_bytes(bytes, (UIntPtr)bytes.Length, out handle));
            return new Speech(handle);
        }

        /// <summary>The rough mode: a coarse mouth from a recording alone.</summary>
        public static Speech FromAudio(float[] samples, int sampleRate)
        {
            SpeechHandle handle;
            FacerigException.Check(Native.fr_speech_from_audio(samples, (UIntPtr)samples.Length, sampleRate, out handle));
            return new Speech(handle);
        }

        /// <summary>espeak-ng text-to-speech (libfacerig_espeak, GPL-3): audio at 22050 Hz and its phonemes.</summary>
        public static Speech Synthesize(string text, string voice)
        {
            SpeechHandle handle;
            FacerigException.Check(Native.fr_tts_synthesize(text, voice, out handle));
            return new Speech(handle);
        }

        public Phoneme[] Phonemes()
        {
            UIntPtr needed;
            Status status = Native.fr_speech_phonemes(Handle, null, UIntPtr.Zero, out needed);
            if (status != Status.BufferTooSmall) FacerigException.Check(status);
            NativePhoneme[] buffer = new NativePhoneme[(int)needed];
            FacerigException.Check(Native.fr_speech_phonemes(Handle, buffer, needed, out needed));
            Phoneme[] phonemes = new Phoneme[buffer.Length];
            for (int i = 0; i < buffer.Length; ++i) phonemes[i] = Phoneme.FromNative(buffer[i]);
            return phonemes;
        }

        public void Dispose() { Handle.Dispose(); }
    }

    /// <summary>A talking character on a rig, driven by your clock (the audio playback position).</summary>
    public sealed class Character : IDisposable
    {
        readonly CharacterHandle handle;
        public int ShapeCount { get; private set; }

        public Character(Rig rig) : this(rig, DefaultOptions()) { }

        public Character(Rig rig, CharacterOptions options)
        {
            FacerigException.Check(Native.fr_character_create(rig.Handle, ref options, out handle));
            ShapeCount = (int)rig.Info.ShapeCount;
        }

        public static CharacterOptions DefaultOptions()
        {
            CharacterOptions options;
            FacerigException.Check(Native.fr_character_default_options(out options));
            return options;
        }

        public void Speak(Speech speech, double startTime)
        {
            FacerigException.Check(Native.fr_character_speak(handle, speech.Handle, startTime));
        }

        public void BeginLine(double startTime) { FacerigException.Check(Native.fr_character_begin_line(handle, startTime)); }

        public void PushPhoneme(Phoneme phoneme)
        {
            NativePhoneme p = phoneme.ToNative();
            FacerigException.Check(Native.fr_character_push_phoneme(handle, ref p));
        }

        public void EndLine() { FacerigException.Check(Native.fr_character_end_line(handle)); }
        public void Stop() { FacerigException.Check(Native.fr_character_stop(handle)); }

        public void SetEmotion(Emotion emotion, float target)
        {
            FacerigException.Check(Native.fr_character_set_emotion(handle, emotion, target));
        }

        public void SetBehaviour(bool blinks, bool gaze)
        {
            FacerigException.Check(Native.fr_character_set_behaviour(handle, blinks ? 1 : 0, gaze ? 1 : 0));
        }

        /// <summary>Per frame: the rig weights at `time` into `weights` (>= ShapeCount). Allocates nothing.</summary>
        public void Update(double time, float[] weights)
        {
            FacerigException.Check(Native.fr_character_update(handle, time, weights, (UIntPtr)weights.Length));
        }

        /// <summary>The viseme with the largest weight at the last Update (0: rest, 1: PP for p/b/m, ...).</summary>
        public int Viseme
        {
            get
            {
                NativeCharacterState state;
                FacerigException.Check(Native.fr_character_get_state(handle, out state));
                return state.Viseme;
            }
        }

        public void Dispose() { handle.Dispose(); }
    }
}
