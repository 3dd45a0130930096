import Foundation
import Localizer
import Maps
import SessionFormat
import SignDetection

/// A check the harness makes beyond "does not crash": something a reader accepted that the project's own
/// writer or a second read then rejects or changes. Reported like a crash.
struct PropertyViolation: Error, CustomStringConvertible {
    /// What broke.
    var description: String
}

/// One fuzz target: an input format and the project code that reads it.
struct FuzzTarget: Sendable {
    /// Name used on the command line and as the corpus sub-directory (Tests/Fuzz/corpus/<name>).
    let name: String
    /// What is exercised.
    let summary: String
    /// Files of a multi-file input that may be dropped by a mutation (optional bundle files).
    let optionalFiles: Set<String>
    /// Runs one input. Throwing an ordinary error is the expected rejection of bad input; throwing
    /// `PropertyViolation` or crashing is a failure. `scratch` is a private, reusable directory.
    let run: @Sendable (_ input: FuzzInput, _ scratch: URL) throws -> Void
    /// Seeds held in the code instead of Tests/Fuzz/corpus (the self-test targets only).
    var builtinSeeds: [FuzzInput]? = nil

    /// Whether the file `name` gets binary (header) rather than text mutations.
    func isBinary(_ name: String) -> Bool { name.lowercased().hasSuffix(".bmp") }

    /// Every target, in campaign order.
    static let all: [FuzzTarget] = [map, bundle, rangeCSV, inavigate, inavigateYAML, inavigateBMP, occam]

    /// Targets that check the harness itself (scripts/fuzz.sh runs them first and expects both to fail):
    /// `selftest-crash` traps on every mutated input of odd length, `selftest-hang` never returns on one whose
    /// length is a multiple of 3. Not part of `all`.
    static let selfTests: [FuzzTarget] = [
        FuzzTarget(name: "selftest-crash", summary: "harness self-test: traps on odd-length mutated inputs", optionalFiles: [],
                   run: { input, _ in
                       let n = input.byteCount
                       if n != 6 && n % 2 == 1 { _ = Int(Double(n) * .infinity) }  // trap: Int(infinity)
                   }, builtinSeeds: [FuzzInput(files: [.init(name: "seed.txt", bytes: Array("123456".utf8))])]),
        FuzzTarget(name: "selftest-hang", summary: "harness self-test: hangs on mutated inputs of length 3k", optionalFiles: [],
                   run: { input, _ in
                       let n = input.byteCount
                       while n != 6 && n % 3 == 0 { usleep(100_000) }
                   }, builtinSeeds: [FuzzInput(files: [.init(name: "seed.txt", bytes: Array("123456".utf8))])]),
    ]

    /// Looks a target up by name (the campaign targets and the self-tests).
    static func named(_ n: String) -> FuzzTarget? { (all + selfTests).first { $0.name == n } }

    /// Map format v1: `MapLoader.load(data:)` (strict JSON parser, decoder, `MapValidator`). A map it accepts
    /// must survive `MapWriter.encode` and a second load unchanged.
    static let map = FuzzTarget(
        name: "map", summary: "MapLoader.load + MapValidator; accepted maps must round-trip through MapWriter",
        optionalFiles: []
    ) { input, _ in
        guard let bytes = input.files.first?.bytes else { return }
        let building = try MapLoader.load(data: Data(bytes), fileName: "fuzz.json")
        let again: Building
        do { again = try MapLoader.load(data: try MapWriter.encode(building), fileName: "rewritten.json") } catch {
            throw PropertyViolation(description: "accepted map fails after MapWriter round trip: \(error)")
        }
        guard again == building else { throw PropertyViolation(description: "map changed in a MapWriter round trip") }
    }

    /// Session bundle v1 written to a temporary directory: `SessionBundle.read` (session.json, frames.jsonl,
    /// observations.jsonl, truth.jsonl, expected.jsonl) and `summary()`.
    static let bundle = FuzzTarget(
        name: "bundle", summary: "SessionBundle.read of session.json + the four .jsonl files, then summary()",
        optionalFiles: ["observations.jsonl", "truth.jsonl", "expected.jsonl", "session.json", "frames.jsonl"]
    ) { input, scratch in
        let dir = scratch.appendingPathComponent("bundle", isDirectory: true)
        try input.write(to: dir)
        let b = try SessionBundle.read(from: dir)
        _ = b.summary().text
    }

    /// Range-observation CSV (`wayfinder range`): `RangeCSV.parse`, then every range method on the first rows.
    static let rangeCSV = FuzzTarget(
        name: "range-csv", summary: "RangeCSV.parse, then each RangeMethod on the first 4 rows",
        optionalFiles: []
    ) { input, _ in
        guard let bytes = input.files.first?.bytes, let text = String(data: Data(bytes), encoding: .utf8) else { return }
        let rows = try RangeCSV.parse(text, fileName: "fuzz.csv")
        for row in rows.prefix(4) {
            for method in RangeMethod.allCases { _ = try? row.estimate(method) }
            _ = try? row.unrollMapping()
        }
    }

    /// iNavigate map folder (info.yml, walls BMP, mapFeatures YAML, navgraph.json) written to a temporary
    /// directory: `InavigateImporter.importBuilding`. An imported building must be writable and loadable.
    static let inavigate = FuzzTarget(
        name: "inavigate", summary: "InavigateImporter.importBuilding on a folder; imports must load after MapWriter",
        optionalFiles: []
    ) { input, scratch in
        let dir = scratch.appendingPathComponent("inavigate", isDirectory: true)
        try input.write(to: dir)
        let (building, _) = try InavigateImporter.importBuilding(from: dir)
        do { _ = try MapLoader.load(data: try MapWriter.encode(building), fileName: "imported.json") } catch {
            throw PropertyViolation(description: "imported building does not load after MapWriter: \(error)")
        }
    }

    /// The iNavigate YAML reader alone (info.yml and mapFeatures_N.yml), with `SimpleYAML.numbers` on
    /// every value.
    static let inavigateYAML = FuzzTarget(
        name: "inavigate-yaml", summary: "SimpleYAML parse + numbers() on every scalar and field", optionalFiles: []
    ) { input, _ in
        guard let bytes = input.files.first?.bytes, let text = String(data: Data(bytes), encoding: .utf8) else { return }
        let y = try SimpleYAML(text: text, file: "fuzz.yml")
        for v in y.scalars.values { _ = SimpleYAML.numbers(v) }
        for r in y.records { for v in r.fields.values { _ = SimpleYAML.numbers(v) } }
    }

    /// The iNavigate wall-mask reader alone: `BMPReader.decode`, then `WallTracer.trace` on images up to
    /// 2^20 pixels.
    static let inavigateBMP = FuzzTarget(
        name: "inavigate-bmp", summary: "BMPReader.decode, then WallTracer.trace (images <= 2^20 px)", optionalFiles: []
    ) { input, _ in
        guard let bytes = input.files.first?.bytes else { return }
        let image = try BMPReader.decode(Data(bytes), file: "fuzz.bmp")
        guard image.pixels.count == image.width * image.height else {
            throw PropertyViolation(description: "decoded \(image.pixels.count) pixels for \(image.width) x \(image.height)")
        }
        guard image.width * image.height <= 1 << 20 else { return }
        _ = WallTracer.trace(mask: image.pixels.map { $0 >= 128 }, width: image.width, height: image.height,
                             minimumComponentPixels: 3)
    }

    /// OCCaM InvisibleMap recording: `OccamImporter.convert`; when it converts, `importWalk` writes a bundle
    /// that `SessionBundle.read` must accept.
    static let occam = FuzzTarget(
        name: "occam", summary: "OccamImporter.convert; converted walks are written and must read back",
        optionalFiles: []
    ) { input, scratch in
        guard let bytes = input.files.first?.bytes else { return }
        let inputDir = scratch.appendingPathComponent("occam-input", isDirectory: true)
        try FuzzInput(files: [.init(name: "walk.json", bytes: bytes)]).write(to: inputDir)
        let file = inputDir.appendingPathComponent("walk.json")
        _ = try OccamImporter.convert(from: file)
        let out = scratch.appendingPathComponent("occam-bundle", isDirectory: true)
        do {
            try OccamImporter.importWalk(from: file, to: out, overwrite: true)
        } catch let e as BundleError {
            throw PropertyViolation(description: "converted walk cannot be written: \(e)")
        }
        do { _ = try SessionBundle.read(from: out) } catch {
            throw PropertyViolation(description: "imported bundle does not read back: \(error)")
        }
    }
}
