import Foundation
import Navigation
import XCTest
@testable import WayfinderCore

/// The walk soundtrack: WAV format, the mixer's timeline, haptic tick patterns, espeak-ng (when installed),
/// and the session's words from the phrase book.
final class SpeechTests: XCTestCase {
    private func u32(_ d: Data, _ at: Int) -> UInt32 { d[at..<at + 4].enumerated().reduce(0) { $0 | UInt32($1.1) << (8 * $1.0) } }
    private func u16(_ d: Data, _ at: Int) -> UInt16 { UInt16(d[at]) | UInt16(d[at + 1]) << 8 }

    func testWAVHeaderAndRoundTrip() throws {
        let audio = PCM16Audio(sampleRate: 22_050, samples: [0, 1, -1, 32767, -32768, 1234])
        let d = WAVFile.encode(audio)
        XCTAssertEqual(d.count, 44 + 12)
        XCTAssertEqual(String(decoding: d[0..<4], as: UTF8.self), "RIFF")
        XCTAssertEqual(u32(d, 4), 36 + 12, "RIFF size = file size - 8")
        XCTAssertEqual(String(decoding: d[8..<16], as: UTF8.self), "WAVEfmt ")
        XCTAssertEqual(u32(d, 16), 16)
        XCTAssertEqual(u16(d, 20), 1, "PCM")
        XCTAssertEqual(u16(d, 22), 1, "mono")
        XCTAssertEqual(u32(d, 24), 22_050)
        XCTAssertEqual(u32(d, 28), 44_100, "byte rate")
        XCTAssertEqual(u16(d, 32), 2, "block align")
        XCTAssertEqual(u16(d, 34), 16, "bits")
        XCTAssertEqual(String(decoding: d[36..<40], as: UTF8.self), "data")
        XCTAssertEqual(u32(d, 40), 12)
        XCTAssertEqual(u16(d, 44 + 6), UInt16(bitPattern: 32767))
        XCTAssertEqual(try WAVFile.decode(d), audio)
    }

    func testWAVReaderTakesAStreamingHeaderAndSkipsOtherChunks() throws {
        var d = WAVFile.encode(PCM16Audio(sampleRate: 16_000, samples: [5, -5, 7]))
        // espeak-ng --stdout writes placeholder sizes: the data then runs to the end of the stream.
        d.replaceSubrange(40..<44, with: [0x00, 0xF0, 0xFF, 0x7F])
        // A LIST chunk before the data.
        var withList = Data(d[0..<36])
        withList.append(contentsOf: Array("LIST".utf8) + [3, 0, 0, 0, 9, 9, 9, 0])
        withList.append(d[36...])
        let audio = try WAVFile.decode(withList)
        XCTAssertEqual(audio.sampleRate, 16_000)
        XCTAssertEqual(audio.samples, [5, -5, 7])
        XCTAssertThrowsError(try WAVFile.decode(Data("RIFF....WAVX".utf8))) { e in
            XCTAssertTrue("\(e)".contains("RIFF/WAVE"), "\(e)")
        }
        var eightBit = WAVFile.encode(PCM16Audio(sampleRate: 8000, samples: [1]))
        eightBit[34] = 8
        XCTAssertThrowsError(try WAVFile.decode(eightBit)) { e in XCTAssertTrue("\(e)".contains("8 bits"), "\(e)") }
    }

    func testSoundtrackPlacesSpeechOnTheTimelineAndCutsOffOnlySpeech() {
        let rate = 8000
        var track = WalkSoundtrack(sampleRate: rate)
        track.speechGain = 1
        let tone = PCM16Audio(sampleRate: rate, samples: [Int16](repeating: 16384, count: 2 * rate))  // 2 s at 0.5
        track.addUtterance(tone, at: 1.0)
        track.addHaptic("turnCue", at: 2.0)
        track.addUtterance(PCM16Audio(sampleRate: rate, samples: [Int16](repeating: 8192, count: rate / 2)), at: 2.5)
        track.extend(toSeconds: 10)
        let out = track.render()
        XCTAssertEqual(out.samples.count, 10 * rate, "the walk's length")
        XCTAssertEqual(out.samples[rate - 1], 0, "silence before the first utterance")
        XCTAssertEqual(out.samples[rate * 3 / 2], Int16((0.5 * 32767).rounded()))
        // The second utterance at 2.5 s cuts the first off: 0.25 from 2.5 to 3.0 s, silence after.
        XCTAssertEqual(out.samples[rate * 27 / 10], Int16((0.25 * 32767).rounded()))
        XCTAssertEqual(out.samples[rate * 32 / 10], 0, "the first utterance (to 3.0 s) was cut off at 2.5 s")
        // The ticks at 2.0 s are still there, mixed over the first utterance (10.25 ms in: a sine peak region).
        XCTAssertNotEqual(out.samples[2 * rate + 82], Int16((0.5 * 32767).rounded()))
    }

    func testSpeechIsResampledToTheTrackRate() {
        var track = WalkSoundtrack(sampleRate: 22_050)
        track.addUtterance(PCM16Audio(sampleRate: 11_025, samples: [Int16](repeating: 1000, count: 11_025)), at: 0)
        XCTAssertEqual(track.render().durationSeconds, 1.0, accuracy: 1e-4)
    }

    func testEachHapticHasItsOwnTickPattern() {
        let names = HapticPattern.allCases.map(\.rawValue)
        XCTAssertEqual(Set(names), ["wrongWay", "offRoute", "turnCue", "arrived"])
        let patterns = names.map { HapticTicks.bursts(for: $0) }
        XCTAssertEqual(Set(patterns.map { $0.map { "\($0.offsetSeconds)/\($0.durationSeconds)/\($0.frequencyHz)" } }).count,
                       names.count, "distinct")
        for n in names {
            XCTAssertGreaterThan(HapticTicks.durationSeconds(of: n), 0.02, n)
            XCTAssertLessThanOrEqual(HapticTicks.durationSeconds(of: n), 0.4, n)
        }
        // Rendered, the ticks are short and audible.
        var track = WalkSoundtrack(sampleRate: 22_050)
        track.addHaptic("wrongWay", at: 0.5)
        let s = track.render().samples
        XCTAssertEqual(s.count, Int(((0.5 + 0.26 + 0.07) * 22_050).rounded()))
        XCTAssertGreaterThan(s.map { abs(Int($0)) }.max() ?? 0, 8000)
    }

    func testMissingSynthesizerIsAClearError() {
        XCTAssertThrowsError(try EspeakSynthesizer(searchPath: "/nonexistent-dir")) { e in
            XCTAssertEqual(e as? SpeechError, .synthesizerMissing("espeak-ng"))
            XCTAssertTrue("\(e)".contains("espeak-ng not found on PATH"), "\(e)")
            XCTAssertTrue("\(e)".contains("apt-get install espeak-ng"), "\(e)")
        }
    }

    func testEspeakRenderingMatchesTheDurationModelAndTheTimeline() throws {
        guard let synthesizer = try? EspeakSynthesizer() else { throw XCTSkip("espeak-ng is not installed") }
        let model = SpeechTimingModel.espeakEnglish
        for text in ["Turn left now.", "Go straight ahead, 8 meters.", "In 8 meters, turn right."] {
            let audio = try synthesizer.render(text)
            XCTAssertEqual(audio.sampleRate, 22_050)
            XCTAssertEqual(audio.durationSeconds, model.durationSeconds(text), accuracy: 0.35, text)
        }
        // A walk of 12 s with two announcements and a haptic: the track is the walk's length (the last
        // utterance ends before it) and the speech is where it was said.
        let audio = try WalkAudioRenderer.render(announcements: [(100.0, "Turn left now."), (105.0, "Arrived.")],
                                                 haptics: [(100.0, "turnCue")], startT: 99, endT: 111,
                                                 synthesizer: synthesizer)
        XCTAssertEqual(audio.samples.count, 12 * 22_050)
        func energy(_ from: Double, _ to: Double) -> Double {
            let a = Int(from * 22_050), b = Int(to * 22_050)
            return audio.samples[a..<b].reduce(0.0) { $0 + Double($1) * Double($1) } / Double(b - a)
        }
        XCTAssertEqual(energy(0, 0.95), 0, "silence before the first event")
        XCTAssertGreaterThan(energy(1.0, 2.0), 1e4, "speech at 1 s")
        XCTAssertEqual(energy(3.0, 5.9), 0, "silence between")
        XCTAssertGreaterThan(energy(6.0, 6.8), 1e4, "speech at 6 s")
    }

    func testSpanishSpeechFromThePhraseBook() throws {
        guard let synthesizer = try? EspeakSynthesizer(voice: "es") else { throw XCTSkip("espeak-ng is not installed") }
        let text = "Gire a la izquierda ahora."
        XCTAssertEqual(try synthesizer.render(text).durationSeconds, SpeechTimingModel.espeakSpanish.durationSeconds(text),
                       accuracy: 0.35)
    }

    func testTrackingPromptsAndStatusComeFromThePhraseBook() throws {
        let es = try PhraseBook.load(language: "es")
        var p = TrackingPromptPolicy(phrases: es)
        var said: String?
        for i in 0..<20 { said = p.update(t: Double(i) / 10, state: .limited, reason: .excessiveMotion) ?? said }
        XCTAssertEqual(said, "Más despacio")
        XCTAssertEqual(TrackingPromptPolicy.prompt(for: .notAvailable, reason: nil, meanLuma: 100, phrases: es),
                       es.phrase("tracking.lost"))
        for c in TrackingPrompt.allCases {
            XCTAssertNotEqual(es.phrase(c.phraseKey), c.phraseKey, "\(c.phraseKey) is in es.json")
            XCTAssertNotEqual(PhraseBook.english.phrase(c.phraseKey), es.phrase(c.phraseKey), c.phraseKey)
        }
        let session = GuidanceSession()
        XCTAssertEqual(session.statusText, "Choose a building")
        session.pipelineOptions.navigator.phrasing.language = "es"
        XCTAssertEqual(session.statusText, "Elija un edificio", "the status switches language at once")
        session.selectBuilding(try TestData.office())
        XCTAssertEqual(session.statusText, es.phrase("status.chooseStart"))
    }
}
