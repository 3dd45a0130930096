// Speech on Linux (and macOS with Homebrew's espeak-ng): the `espeak-ng` command from Debian's package,
// run as a child process. Renders an utterance to samples (`--stdout`, for the walk soundtrack) or speaks
// it on the default audio device. The iPhone speaks with AVSpeechSynthesizer instead (App/iOS), so this
// file is compiled only where processes exist.
#if os(Linux) || os(macOS)
import Foundation

/// Why speech could not be produced.
public enum SpeechError: Error, CustomStringConvertible, Sendable, Equatable {
    /// The synthesizer command is not installed (not on PATH).
    case synthesizerMissing(String)
    /// The synthesizer ran but failed; the text says how.
    case synthesizerFailed(String)

    /// Message for people.
    public var description: String {
        switch self {
        case .synthesizerMissing(let name):
            let what = name.contains("/") ? "\(name) is not an executable file" : "\(name) not found on PATH"
            return "\(what): speech needs espeak-ng (Debian: apt-get install espeak-ng; scripts/setup.sh installs it)"
        case .synthesizerFailed(let m): return m
        }
    }
}

/// The espeak-ng command line: text in, 16-bit mono PCM out (22 050 Hz).
public struct EspeakSynthesizer: Sendable {
    /// Absolute path of the executable.
    public let executable: String
    /// espeak-ng voice, e.g. "en", "es" (the phrase book's language).
    public var voice: String
    /// Speaking rate, words per minute (espeak-ng's default and the duration model's reference: 175).
    public var wordsPerMinute: Int

    /// Finds `name` on PATH (or takes it as a path when it contains "/"); throws
    /// `SpeechError.synthesizerMissing` when there is none.
    public init(voice: String = "en", wordsPerMinute: Int = 175, name: String = "espeak-ng",
                searchPath: String? = ProcessInfo.processInfo.environment["PATH"]) throws {
        guard let found = Self.locate(name, searchPath: searchPath) else { throw SpeechError.synthesizerMissing(name) }
        executable = found
        self.voice = voice
        self.wordsPerMinute = wordsPerMinute
    }

    /// The executable file `name` in the folders of `searchPath` (colon-separated), nil if none.
    public static func locate(_ name: String, searchPath: String?) -> String? {
        let fm = FileManager.default
        if name.contains("/") { return fm.isExecutableFile(atPath: name) ? name : nil }
        for dir in (searchPath ?? "").split(separator: ":") where !dir.isEmpty {
            let candidate = "\(dir)/\(name)"
            if fm.isExecutableFile(atPath: candidate) { return candidate }
        }
        return nil
    }

    private func arguments(_ text: String) -> [String] {
        // "--" ends the options: a phrase starting with "-" is still text.
        ["-v", voice, "-s", String(wordsPerMinute), "--stdout", "--", text]
    }

    /// Renders `text` to samples (`espeak-ng --stdout`, a WAV stream read by `WAVFile.decode`).
    public func render(_ text: String) throws -> PCM16Audio {
        let p = Process()
        p.executableURL = URL(fileURLWithPath: executable)
        p.arguments = arguments(text)
        let out = Pipe(), err = Pipe()
        p.standardOutput = out
        p.standardError = err
        do { try p.run() } catch {
            throw SpeechError.synthesizerFailed("\(executable): cannot run (\(error.localizedDescription))")
        }
        // Read before waiting: a long utterance fills the pipe.
        let data = out.fileHandleForReading.readDataToEndOfFile()
        let errors = err.fileHandleForReading.readDataToEndOfFile()
        p.waitUntilExit()
        guard p.terminationStatus == 0 else {
            let message = String(decoding: errors, as: UTF8.self).trimmingCharacters(in: .whitespacesAndNewlines)
            throw SpeechError.synthesizerFailed("\(executable) -v \(voice) exited \(p.terminationStatus): \(message)")
        }
        do { return try WAVFile.decode(data) } catch {
            throw SpeechError.synthesizerFailed("\(executable) -v \(voice) --stdout: \(error)")
        }
    }

    /// Starts speaking `text` on the default audio device and returns at once; the returned process can
    /// be stopped (`terminate()`) to cut the utterance off. espeak-ng's own messages (e.g. no sound card)
    /// are collected in the `Pipe` that is the process's `standardError` (read it once it has exited).
    public func speak(_ text: String) throws -> Process {
        let p = Process()
        p.executableURL = URL(fileURLWithPath: executable)
        p.arguments = ["-v", voice, "-s", String(wordsPerMinute), "--", text]
        p.standardOutput = FileHandle.nullDevice
        p.standardError = Pipe()
        do { try p.run() } catch {
            throw SpeechError.synthesizerFailed("\(executable): cannot run (\(error.localizedDescription))")
        }
        return p
    }
}

/// Renders a walk's announcements and haptics into one soundtrack with espeak-ng.
public enum WalkAudioRenderer {
    /// The track of `announcements` (seconds on the walk's clock, text) and `haptics` (seconds, pattern
    /// name) from `startT`, at least `endT - startT` long. Each distinct text is synthesized once.
    public static func render(announcements: [(t: Double, text: String)], haptics: [(t: Double, pattern: String)],
                              startT: Double, endT: Double, synthesizer: EspeakSynthesizer) throws -> PCM16Audio {
        var cache: [String: PCM16Audio] = [:]
        var track = WalkSoundtrack()
        for a in announcements.sorted(by: { $0.t < $1.t }) {
            let audio: PCM16Audio
            if let cached = cache[a.text] { audio = cached } else {
                audio = try synthesizer.render(a.text)
                cache[a.text] = audio
            }
            track.addUtterance(audio, at: a.t - startT)
        }
        for h in haptics { track.addHaptic(h.pattern, at: h.t - startT) }
        track.extend(toSeconds: endT - startT)
        return track.render()
    }
}
#endif
