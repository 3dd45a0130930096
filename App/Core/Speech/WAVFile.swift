// A minimal RIFF/WAVE reader and writer for 16-bit PCM, written for the walk soundtrack
// (`wayfinder replay --audio`): the writer emits the canonical 44-byte header (RIFF, fmt with PCM format 1,
// data); the reader accepts any chunk order and the "unknown length" sizes that streaming writers such as
// `espeak-ng --stdout` put in the header (0x7FFFF000-ish or 0xFFFFFFFF): the data then runs to the end.
// Format reference: Microsoft/IBM RIFF WAVE (Multimedia Programming Interface and Data Specifications 1.0).
import Foundation

/// 16-bit PCM audio, one or more interleaved channels.
public struct PCM16Audio: Sendable, Equatable {
    /// Samples per second per channel, Hz.
    public var sampleRate: Int
    /// Interleaved channels (1 = mono).
    public var channels: Int
    /// Interleaved samples.
    public var samples: [Int16]

    /// Creates audio from interleaved samples.
    public init(sampleRate: Int, channels: Int = 1, samples: [Int16]) {
        self.sampleRate = sampleRate; self.channels = channels; self.samples = samples
    }

    /// Frames (samples per channel).
    public var frameCount: Int { channels > 0 ? samples.count / channels : 0 }
    /// Duration, seconds.
    public var durationSeconds: Double { sampleRate > 0 ? Double(frameCount) / Double(sampleRate) : 0 }

    /// The audio as mono floats in [-1, 1] (channels averaged).
    public func monoFloats() -> [Float] {
        guard channels > 1 else { return samples.map { Float($0) / 32768 } }
        return (0..<frameCount).map { f in
            var sum: Float = 0
            for c in 0..<channels { sum += Float(samples[f * channels + c]) }
            return sum / Float(channels) / 32768
        }
    }
}

/// Why a WAV file could not be read.
public enum WAVError: Error, CustomStringConvertible, Sendable, Equatable {
    /// Not a RIFF/WAVE file, or a header field is inconsistent; the text names the field.
    case malformed(String)
    /// A valid WAV file in a format this reader does not handle (only PCM 16-bit).
    case unsupported(String)

    /// Message for people.
    public var description: String {
        switch self {
        case .malformed(let m): return "not a readable WAV file: \(m)"
        case .unsupported(let m): return "unsupported WAV format: \(m)"
        }
    }
}

/// Reads and writes 16-bit PCM WAV.
public enum WAVFile {
    /// Size of the header `encode` writes, bytes.
    public static let headerBytes = 44

    /// The file bytes of `audio`: "RIFF" size "WAVE", "fmt " (16 bytes: PCM, channels, rate, byte rate,
    /// block align, 16 bits), "data" size, then the little-endian samples.
    public static func encode(_ audio: PCM16Audio) -> Data {
        var d = Data(capacity: headerBytes + audio.samples.count * 2)
        func u32(_ v: UInt32) { withUnsafeBytes(of: v.littleEndian) { d.append(contentsOf: $0) } }
        func u16(_ v: UInt16) { withUnsafeBytes(of: v.littleEndian) { d.append(contentsOf: $0) } }
        let dataBytes = UInt32(audio.samples.count * 2)
        d.append(contentsOf: Array("RIFF".utf8)); u32(36 + dataBytes); d.append(contentsOf: Array("WAVE".utf8))
        d.append(contentsOf: Array("fmt ".utf8)); u32(16); u16(1); u16(UInt16(audio.channels)); u32(UInt32(audio.sampleRate))
        u32(UInt32(audio.sampleRate * audio.channels * 2)); u16(UInt16(audio.channels * 2)); u16(16)
        d.append(contentsOf: Array("data".utf8)); u32(dataBytes)
        audio.samples.withUnsafeBufferPointer { buf in
            for s in buf { withUnsafeBytes(of: s.littleEndian) { d.append(contentsOf: $0) } }
        }
        return d
    }

    /// Writes `audio` to `url` (atomically).
    public static func write(_ audio: PCM16Audio, to url: URL) throws {
        try encode(audio).write(to: url, options: .atomic)
    }

    /// Parses WAV bytes. Chunks other than "fmt " and "data" are skipped; a data size beyond the end of the
    /// bytes (a streaming writer's placeholder) means "to the end".
    public static func decode(_ data: Data) throws -> PCM16Audio {
        let bytes = [UInt8](data)
        func u32(_ at: Int) -> UInt32 {
            UInt32(bytes[at]) | UInt32(bytes[at + 1]) << 8 | UInt32(bytes[at + 2]) << 16 | UInt32(bytes[at + 3]) << 24
        }
        func u16(_ at: Int) -> UInt16 { UInt16(bytes[at]) | UInt16(bytes[at + 1]) << 8 }
        func tag(_ at: Int) -> String { String(decoding: bytes[at..<at + 4], as: UTF8.self) }
        guard bytes.count >= 12, tag(0) == "RIFF", tag(8) == "WAVE" else {
            throw WAVError.malformed("no RIFF/WAVE header (\(bytes.count) bytes)")
        }
        var at = 12
        var format: (channels: Int, rate: Int, bits: Int)?
        while at + 8 <= bytes.count {
            let id = tag(at)
            let size = Int(u32(at + 4))
            let body = at + 8
            if id == "fmt " {
                guard size >= 16, body + 16 <= bytes.count else { throw WAVError.malformed("fmt chunk of \(size) bytes") }
                let code = u16(body)
                let channels = Int(u16(body + 2)), rate = Int(u32(body + 4)), bits = Int(u16(body + 14))
                guard code == 1 || code == 0xFFFE else { throw WAVError.unsupported("format code \(code), not PCM") }
                guard bits == 16 else { throw WAVError.unsupported("\(bits) bits per sample, not 16") }
                guard channels >= 1, rate >= 1 else { throw WAVError.malformed("\(channels) channels at \(rate) Hz") }
                format = (channels, rate, bits)
            } else if id == "data" {
                guard let format else { throw WAVError.malformed("data chunk before the fmt chunk") }
                let end = min(bytes.count, body + size)
                let count = (end - body) / 2
                var samples = [Int16](repeating: 0, count: count)
                for i in 0..<count { samples[i] = Int16(bitPattern: u16(body + 2 * i)) }
                let whole = samples.count - samples.count % format.channels
                return PCM16Audio(sampleRate: format.rate, channels: format.channels, samples: Array(samples.prefix(whole)))
            }
            at = body + size + (size & 1)
        }
        throw WAVError.malformed(format == nil ? "no fmt chunk" : "no data chunk")
    }
}
