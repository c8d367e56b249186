"""Speaking through the Python binding: lips close on p/b/m at 60 fps, streaming, the rough mode."""
import numpy as np
import pytest

import facerig
from conftest import lip_pair

TRACK = """{"format": "facerig-phoneme-track", "version": 1, "text": "a pa ba ma", "language": "en-us",
 "phonemes": [
  {"start": 0.00, "duration": 0.10, "symbol": "_:"},
  {"start": 0.10, "duration": 0.12, "symbol": "a#", "word_start": true},
  {"start": 0.22, "duration": 0.04, "symbol": "p", "word_start": true},
  {"start": 0.26, "duration": 0.12, "symbol": "A:"},
  {"start": 0.38, "duration": 0.03, "symbol": "b", "word_start": true},
  {"start": 0.41, "duration": 0.12, "symbol": "A:"},
  {"start": 0.53, "duration": 0.05, "symbol": "m", "word_start": true},
  {"start": 0.58, "duration": 0.15, "symbol": "A:"},
  {"start": 0.73, "duration": 0.20, "symbol": "_:"}]}"""

BILABIALS = {"p", "b", "m"}


def apertures(rig, character, seconds, fps=60):
    """The lip aperture per frame at `fps`, blending each frame into one reused array."""
    upper, lower = lip_pair(rig)
    weights = np.empty(rig.shape_count, np.float32)
    positions = np.empty((rig.vertex_count, 3), np.float32)
    times = np.arange(0.0, seconds, 1.0 / fps)
    result = []
    for t in times:
        character.update(t, out=weights)
        rig.blend(weights, out=positions)
        result.append(np.linalg.norm(positions[upper] - positions[lower]))
    return times, np.array(result)


def check_bilabials_close(phonemes, times, aperture):
    widest = aperture.max()
    assert widest > 0.5  # cm: the mouth opens
    closures = 0
    for p in phonemes:
        if p.symbol not in BILABIALS:
            continue
        during = (times >= p.start - 0.06) & (times <= p.start + max(p.duration, 0.03))
        assert aperture[during].min() < 0.1 * widest, f"{p.symbol} at {p.start:.3f} s"
        closures += 1
    return closures


def test_a_tts_line_at_60_fps_closes_the_lips_on_every_p_b_m(rig):
    pytest.importorskip("facerig.tts")
    from facerig import tts
    speech = tts.synthesize("Bob bought a map from a puppet maker. Maybe my mom bakes apple pie.", "en-us")
    samples, rate = speech.audio
    assert rate == 22050 and samples.size > rate
    phonemes = speech.phonemes
    with facerig.Character(rig) as character:
        character.speak(speech)
        times, aperture = apertures(rig, character, samples.size / rate + 0.3)
    assert check_bilabials_close(phonemes, times, aperture) >= 10
    assert aperture[-1] < 0.05 * aperture.max()  # rests after the line


def test_phonemes_pushed_as_they_arrive_give_the_weights_of_the_whole_line(rig):
    speech = facerig.Speech.from_track(TRACK)
    whole, pushed = facerig.Character(rig, seed=3), facerig.Character(rig, seed=3)
    whole.speak(speech, 0.25)
    pushed.begin_line(0.25)
    for phoneme in speech.phonemes:
        pushed.push_phoneme(phoneme)
    pushed.end_line()
    for t in np.arange(0.0, 1.5, 1 / 60):
        assert np.array_equal(whole.update(t), pushed.update(t))


def test_a_track_file_and_its_text_give_the_same_line(tmp_path):
    (tmp_path / "line.json").write_text(TRACK)
    from_file = facerig.Speech.from_track(tmp_path / "line.json").phonemes
    assert from_file == facerig.Speech.from_track(TRACK).phonemes
    assert [p.symbol for p in from_file][:3] == ["_:", "a#", "p"] and from_file[2].word_start
    assert facerig.Speech(from_file).phonemes == from_file  # through fr_speech_create


def test_emotion_and_state(rig):
    character = facerig.Character(rig, blinks=False, gaze=False)
    character.set_emotion("joy", 1.0)
    weights = character.update(0.0)
    weights = character.update(2.0)
    smile = rig.shape_names.index("mouthSmileLeft")
    assert weights[smile] > 0.3
    assert character.state["viseme"] == "sil" and not character.state["talking"]


def test_the_rough_mode_streams_phonemes_from_audio_alone(rig):
    pytest.importorskip("facerig.tts")
    from facerig import tts
    samples, rate = tts.synthesize("Papa met Bob at noon.", "en-us").audio
    stream = facerig.AudioStream.rough(rate)
    streamed = []
    for at in range(0, samples.size, rate // 10):  # 100 ms chunks
        streamed += stream.push(samples[at:at + rate // 10])
    streamed += stream.finish()
    whole = facerig.Speech.from_audio(samples, rate).phonemes
    assert len(streamed) > 5 and len(whole) > 5
    assert abs(streamed[-1].start + streamed[-1].duration - samples.size / rate) < 0.05
    starts = [p.start for p in streamed]
    assert starts == sorted(starts)


def test_streaming_alignment_times_the_reference_phonemes_on_a_recording():
    pytest.importorskip("facerig.tts")
    from facerig import tts
    recording = tts.synthesize("Maybe my mom bakes apple pie.", "en-us")
    reference = tts.synthesize("Maybe my mom bakes apple pie.", "en-us")
    samples, rate = recording.audio
    stream = facerig.AudioStream.aligned(reference)
    aligned = []
    for at in range(0, samples.size, rate // 20):
        aligned += stream.push(samples[at:at + rate // 20])
    aligned += stream.finish()
    truth = recording.phonemes
    assert [p.symbol for p in aligned] == [p.symbol for p in truth]
    errors = sorted(abs(a.start - b.start) for a, b in zip(aligned, truth))
    assert errors[len(errors) // 2] < 0.02  # median boundary within 20 ms


def test_a_whole_recording_aligns_to_a_reference_and_says_whether_they_fit():
    pytest.importorskip("facerig.tts")
    from facerig import tts
    recording = tts.synthesize("Maybe my mom bakes apple pie.", "en-us")
    samples, rate = recording.audio
    padded = np.concatenate([np.zeros(rate // 2, np.float32), samples])  # half a second of silence first
    reference = tts.synthesize("Maybe my mom bakes apple pie.", "en-us")
    aligned = facerig.Speech.aligned(reference, padded, rate)
    truth = recording.phonemes
    assert [p.symbol for p in aligned.phonemes] == [p.symbol for p in truth]
    errors = sorted(abs(a.start - (b.start + 0.5)) for a, b in zip(aligned.phonemes, truth) if b.symbol[0] != "_")
    assert errors[len(errors) // 2] < 0.02 and errors[-1] < 0.06
    confidence, tempo, fits = aligned.fit
    assert fits and confidence > 0.1 and 0.8 < tempo < 1.25
    other = tts.synthesize("The quick brown fox jumps over the lazy dog, twice.", "en-us")
    assert facerig.Speech.aligned(other, padded, rate).fit[0] < confidence / 2
    noise = (np.random.default_rng(1).normal(size=padded.size) * 0.1).astype(np.float32)
    _, _, fits = facerig.Speech.aligned(reference, noise, rate).fit
    assert not fits
    with pytest.raises(facerig.FacerigError, match="resample it first"):
        facerig.Speech.aligned(reference, padded, rate // 2)


def test_a_recording_and_its_transcript_align():
    pytest.importorskip("facerig.tts")
    from facerig import tts
    recording = tts.synthesize("Pam brought the map.", "en-us")
    samples, rate = recording.audio
    aligned = tts.align(samples, rate, "Pam brought the map.", "en-us")
    assert [p.symbol for p in aligned.phonemes] == [p.symbol for p in recording.phonemes]
    assert aligned.audio[1] == rate


def test_streaming_tts_hands_over_audio_and_phonemes_as_they_are_made(rig):
    pytest.importorskip("facerig.tts")
    from facerig import tts
    text = "Bob bought a map from a puppet maker."
    chunks, phonemes = [], []
    rate = tts.synthesize_streaming(text, "en-us", on_audio=chunks.append, on_phoneme=phonemes.append)
    whole = tts.synthesize(text, "en-us")
    assert rate == 22050 and len(chunks) > 1
    assert [p.symbol for p in phonemes] == [p.symbol for p in whole.phonemes]
    samples = np.concatenate(chunks)
    assert abs(samples.size - whole.audio[0].size) < 0.05 * samples.size
    # A character fed the streamed phonemes closes its lips on the bilabials.
    character = facerig.Character(rig)
    character.begin_line(0.0)
    for phoneme in phonemes:
        character.push_phoneme(phoneme)
    character.end_line()
    times, aperture = apertures(rig, character, samples.size / rate + 0.3)
    assert check_bilabials_close(phonemes, times, aperture) >= 5


def test_streaming_tts_stops_when_a_callback_says_so():
    pytest.importorskip("facerig.tts")
    from facerig import tts
    seen = []
    with pytest.raises(facerig.CancelledError, match="stopped"):
        tts.synthesize_streaming("Maybe my mom bakes apple pie.", "en-us",
                                 on_phoneme=lambda p: seen.append(p) or len(seen) >= 3)
    assert len(seen) == 3
    with pytest.raises(ZeroDivisionError):
        tts.synthesize_streaming("Maybe.", "en-us", on_audio=lambda samples: 1 / 0)


def test_a_recording_read_from_a_file_and_its_errors(tmp_path):
    """fr_speech_load_audio_file: the samples of a WAV (written here by Python's wave module) and
    what an unreadable or missing file says."""
    import wave
    rate = 16000
    tone = (0.5 * np.sin(2 * np.pi * 220 * np.arange(rate // 2) / rate)).astype(np.float32)
    stereo = np.stack([tone, -tone / 2], axis=1)
    with wave.open(str(tmp_path / "tone.wav"), "wb") as out:
        out.setnchannels(2)
        out.setsampwidth(2)
        out.setframerate(rate)
        out.writeframes((stereo * 32767).astype("<i2").tobytes())
    speech = facerig.Speech.from_audio_file(tmp_path / "tone.wav")
    samples, read_rate = speech.audio
    assert read_rate == rate and speech.phonemes == []
    assert np.allclose(samples, tone / 4, atol=1e-4)  # the channels averaged
    assert len(facerig.Speech.from_audio(samples, rate).phonemes) > 0  # the rough mode takes them
    (tmp_path / "notes.wav").write_text("not audio")
    with pytest.raises(facerig.FormatError, match="notes.wav"):
        facerig.Speech.from_audio_file(tmp_path / "notes.wav")
    with pytest.raises(facerig.FileError, match="missing.wav"):
        facerig.Speech.from_audio_file(tmp_path / "missing.wav")
