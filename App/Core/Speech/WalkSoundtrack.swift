// The sound of a walk on its own timeline: every utterance where it was said and a short tick pattern for
// every haptic event, mixed into one mono track (what `wayfinder replay --audio OUT.wav` writes, so a
// trainer hears what the traveler heard and felt, and when). Synthesizer-independent: the utterances'
// samples come from outside (espeak-ng on Linux; see `EspeakSynthesizer`).
import Foundation

/// One short tone burst of a haptic tick pattern.
public struct TickBurst: Sendable, Equatable {
    /// Start after the pattern's start, seconds.
    public var offsetSeconds: Double
    /// Length, seconds.
    public var durationSeconds: Double
    /// Tone, Hz.
    public var frequencyHz: Double
}

/// The audible stand-in for each haptic pattern: one distinct rhythm and pitch per event, short enough
/// (at most 0.4 s) to sit under speech. Names are `HapticPattern` raw values.
public enum HapticTicks {
    /// Bursts of `pattern` ("turnCue", "wrongWay", "offRoute", "arrived"); an unknown name gets one
    /// neutral 40 ms tick at 800 Hz, so nothing felt goes unheard.
    /// - turnCue: two crisp high ticks (1500 Hz, 25 ms, 100 ms apart), felt with a turn cue;
    /// - wrongWay: three low buzzes (200 Hz, 70 ms, 130 ms apart);
    /// - offRoute: one long low buzz (300 Hz, 350 ms);
    /// - arrived: three rising ticks (600, 900, 1200 Hz, 40 ms, 110 ms apart).
    public static func bursts(for pattern: String) -> [TickBurst] {
        switch pattern {
        case "turnCue":
            return [0, 0.1].map { TickBurst(offsetSeconds: $0, durationSeconds: 0.025, frequencyHz: 1500) }
        case "wrongWay":
            return [0, 0.13, 0.26].map { TickBurst(offsetSeconds: $0, durationSeconds: 0.07, frequencyHz: 200) }
        case "offRoute":
            return [TickBurst(offsetSeconds: 0, durationSeconds: 0.35, frequencyHz: 300)]
        case "arrived":
            return [(0.0, 600.0), (0.11, 900.0), (0.22, 1200.0)].map {
                TickBurst(offsetSeconds: $0.0, durationSeconds: 0.04, frequencyHz: $0.1)
            }
        default:
            return [TickBurst(offsetSeconds: 0, durationSeconds: 0.04, frequencyHz: 800)]
        }
    }

    /// Length of a pattern, seconds (end of its last burst).
    public static func durationSeconds(of pattern: String) -> Double {
        bursts(for: pattern).map { $0.offsetSeconds + $0.durationSeconds }.max() ?? 0
    }
}

/// Mixes a walk's speech and haptics into one mono 16-bit track.
public struct WalkSoundtrack {
    /// Output sample rate, Hz (espeak-ng's 22 050 Hz by default).
    public let sampleRate: Int
    /// Gain of speech, 0...1.
    public var speechGain: Float = 0.9
    /// Peak amplitude of haptic ticks, 0...1.
    public var tickGain: Float = 0.35
    /// Speech and ticks are kept apart so that cutting an utterance off leaves the ticks.
    private var speech: [Float] = []
    private var ticks: [Float] = []
    private var lastUtterance: (start: Int, end: Int)? = nil

    /// Creates an empty track.
    public init(sampleRate: Int = 22_050) { self.sampleRate = max(1, sampleRate) }

    /// Length of the track so far, seconds.
    public var durationSeconds: Double { Double(max(speech.count, ticks.count)) / Double(sampleRate) }

    private func index(_ t: Double) -> Int { max(0, Int((t * Double(sampleRate)).rounded())) }

    private mutating func ensure(_ n: Int) {
        if speech.count < n { speech += [Float](repeating: 0, count: n - speech.count) }
        if ticks.count < n { ticks += [Float](repeating: 0, count: n - ticks.count) }
    }

    /// Extends the track with silence to at least `seconds` (the walk's end).
    public mutating func extend(toSeconds seconds: Double) { ensure(index(seconds)) }

    /// Places an utterance at `t` seconds. Speech is one voice: an utterance still playing at `t` is cut
    /// off there (the announcement policy only starts speech over speech to interrupt it, as the phone's
    /// synthesizer does). `audio` at another rate is resampled linearly.
    public mutating func addUtterance(_ audio: PCM16Audio, at t: Double) {
        let start = index(t)
        if let last = lastUtterance, last.end > start {
            for i in start..<min(last.end, speech.count) { speech[i] = 0 }
        }
        let mono = audio.monoFloats()
        let resampled = audio.sampleRate == sampleRate ? mono : Self.resample(mono, from: audio.sampleRate, to: sampleRate)
        ensure(start + resampled.count)
        for (k, s) in resampled.enumerated() { speech[start + k] += speechGain * s }
        lastUtterance = (start, start + resampled.count)
    }

    /// Places the tick pattern of haptic `pattern` at `t` seconds (added to whatever plays then). Each
    /// burst is a sine with 5 ms raised-cosine fades, so it clicks without a pop.
    public mutating func addHaptic(_ pattern: String, at t: Double) {
        for b in HapticTicks.bursts(for: pattern) {
            let start = index(t + b.offsetSeconds)
            let n = max(1, Int((b.durationSeconds * Double(sampleRate)).rounded()))
            ensure(start + n)
            let fade = max(1, min(n / 2, Int(0.005 * Double(sampleRate))))
            for k in 0..<n {
                var env: Float = 1
                if k < fade { env = 0.5 - 0.5 * Float(cos(Double.pi * Double(k) / Double(fade))) }
                if n - 1 - k < fade { env = min(env, 0.5 - 0.5 * Float(cos(Double.pi * Double(n - 1 - k) / Double(fade)))) }
                let phase = 2 * Double.pi * b.frequencyHz * Double(k) / Double(sampleRate)
                ticks[start + k] += tickGain * env * Float(sin(phase))
            }
        }
    }

    /// The mixed track, clipped to 16 bits.
    public func render() -> PCM16Audio {
        PCM16Audio(sampleRate: sampleRate, channels: 1,
                   samples: zip(speech, ticks).map { Int16(max(-32768, min(32767, (($0 + $1) * 32767).rounded()))) })
    }

    /// Linear-interpolation resampling of mono samples.
    static func resample(_ x: [Float], from: Int, to: Int) -> [Float] {
        guard !x.isEmpty, from > 0, to > 0 else { return [] }
        let n = Int((Double(x.count) * Double(to) / Double(from)).rounded())
        return (0..<n).map { i in
            let p = Double(i) * Double(from) / Double(to)
            let j = min(Int(p), x.count - 1), f = Float(p - Double(j))
            return j + 1 < x.count ? x[j] * (1 - f) + x[j + 1] * f : x[j]
        }
    }
}
