#!/usr/bin/env python3
"""Writes audio-reactive.flac, the sound of patches/audio-reactive.ron (Python
and ffmpeg only): four seconds of mono 22.05 kHz at 120 BPM, a kick on every
beat, a hi-hat between, a pluck at 330 Hz on every beat, a bell at 1.2 kHz
on odd beats and a bass line, so each of four logarithmic Spectrum bands from
40 Hz to 8 kHz has its own instrument, and the Envelope pulses with the kick. It loops
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

    def add(at, seconds, sample):
        for k in range(int(seconds * RATE)):
            if at + k < n:
                out[at + k] += sample(k / RATE)

    for b in range(BEATS):
        start = b * beat
        # Kick (the lowest band): a sine falling from 120 to 45 Hz, 0.25 s.
        phase = [0.0]

        def kick(t):
            phase[0] += 2 * math.pi * (45 + 75 * math.exp(-t / 0.03)) / RATE
            return 0.6 * math.sin(phase[0]) * math.exp(-t / 0.08)

        add(start, 0.25, kick)
        # A pluck on E4 (330 Hz, the second band) every beat, louder on odd beats.
        level = 0.3 if b % 2 else 0.15
        add(start, 0.4, lambda t: level * math.sin(2 * math.pi * 330 * t) * math.exp(-t / 0.12))
        # A bell at 1.2 kHz (the third band) on odd beats.
        if b % 2:
            add(start, 0.5, lambda t: 0.25 * math.sin(2 * math.pi * 1200 * t) * math.exp(-t / 0.15))
        # A metallic hi-hat (three high partials: the top band) on every eighth note,
        # accented off the beat.
        for half, accent in ((0, 0.06), (beat // 2, 0.15)):
            add(start + half, 0.06, lambda t, a=accent: a * math.exp(-t / 0.02) * sum(
                math.sin(2 * math.pi * f * t) for f in (3100.0, 4700.0, 6300.0)))
        # Noise for air under the hat.
        add(start + beat // 2, 0.03, lambda t: 0.05 * noise() * math.exp(-t / 0.01))
    # A quiet bass line, two beats a note: A1, C2, E1, G1.
    for i, freq in enumerate([55.0, 65.41, 41.2, 49.0]):
        start = i * 2 * beat
        for k in range(2 * beat):
            t = k / RATE
            fade = min(1.0, t / 0.01, (2 * beat - k) / RATE / 0.01)
            out[start + k] += 0.12 * fade * math.sin(2 * math.pi * freq * t)
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
