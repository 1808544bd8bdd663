#!/usr/bin/env python3
"""Writes audio-reactive.flac, the sound of patches/audio-reactive.ron (Python
and ffmpeg only): four seconds of mono 22.05 kHz at 120 BPM, a kick on every
beat, a hi-hat between, and a bass note changing every two beats, so the
Spectrum's low, middle and high bands and the Envelope all move. It loops
cleanly (eight beats exactly).
"""
import math
import os
import struct
import subprocess
import tempfile
import wave

RATE = 22050
BPM = 120
BEATS = 8


def main():
    beat = RATE * 60 // BPM
    n = beat * BEATS
    out = [0.0] * n
    seed = 12345

    def noise():
        nonlocal seed
        # A fixed linear congruential generator: the same file every time.
        seed = (seed * 1103515245 + 12345) & 0x7FFFFFFF
        return seed / 0x3FFFFFFF - 1.0

    for b in range(BEATS):
        start = b * beat
        # Kick: a sine falling from 120 to 45 Hz, 0.25 s.
        phase = 0.0
        for k in range(int(0.25 * RATE)):
            t = k / RATE
            f = 45 + 75 * math.exp(-t / 0.03)
            phase += 2 * math.pi * f / RATE
            out[start + k] += 0.8 * math.sin(phase) * math.exp(-t / 0.08)
        # Hi-hat on the off-beat: 40 ms of differenced noise (bright).
        hat = start + beat // 2
        last = 0.0
        for k in range(int(0.04 * RATE)):
            t = k / RATE
            x = noise()
            out[hat + k] += 0.25 * (x - last) * math.exp(-t / 0.012)
            last = x
    # Bass notes, two beats each: A2, C3, E2, G2.
    for i, freq in enumerate([110.0, 130.81, 82.41, 98.0]):
        start = i * 2 * beat
        for k in range(2 * beat):
            t = k / RATE
            fade = min(1.0, t / 0.01, (2 * beat - k) / RATE / 0.01)
            out[start + k] += 0.2 * fade * math.sin(2 * math.pi * freq * t)
    frames = b"".join(struct.pack("<h", int(max(-1.0, min(1.0, s)) * 32767)) for s in out)
    here = os.path.dirname(os.path.abspath(__file__))
    with tempfile.TemporaryDirectory() as tmp:
        wav = os.path.join(tmp, "audio-reactive.wav")
        with wave.open(wav, "wb") as w:
            w.setnchannels(1)
            w.setsampwidth(2)
            w.setframerate(RATE)
            w.writeframes(frames)
        subprocess.run(
            ["ffmpeg", "-y", "-loglevel", "error", "-i", wav, "-c:a", "flac",
             "-compression_level", "12", "-map_metadata", "-1", "-fflags", "+bitexact",
             os.path.join(here, "audio-reactive.flac")],
            check=True,
        )


if __name__ == "__main__":
    main()
