import Foundation
import XCTest

/// `wayfinder import-inavigate` (the real Smith-Kettlewell floors, then validate-map on the result),
/// `import-occam` (a real ARKit walk, then inspect on the bundle) and `range --input` on the committed fixture.
/// The shared data lives outside the repository (../shared); tests that need it are skipped when it is absent.
final class ImportAndRangeCommandTests: XCTestCase {
    private var directory: URL!

    override func setUpWithError() throws {
        directory = try CLI.makeTemporaryDirectory("import")
    }

    override func tearDownWithError() throws {
        if let directory { try? FileManager.default.removeItem(at: directory) }
    }

    /// A folder of ../shared/data, or XCTSkip when the shared data is not mounted.
    private func sharedData(_ name: String) throws -> URL {
        let url = CLI.repositoryRoot.deletingLastPathComponent().appendingPathComponent("shared/data/\(name)")
        guard FileManager.default.fileExists(atPath: url.path) else { throw XCTSkip("\(url.path) is not present") }
        return url
    }

    func testImportInavigateWritesAMapThatValidates() throws {
        let source = try sharedData("skeri_inavigate")
        let out = directory.appendingPathComponent("skeri.json").path
        let r = try CLI.run(["import-inavigate", source.path, "-o", out])
        r.assertExit(0)
        r.assertStdout(contains: "wrote \(out): ")
        r.assertStderr(contains: "floor ")
        let v = try CLI.run(["validate-map", out])
        v.assertExit(0)
        v.assertStdout(contains: "ok: \(out): ")
        // The importer's figures and the validator's agree on the counts they both print.
        for figure in ["floors", "walls", "signs", "POIs", "nodes"] {
            let imported = Self.count(of: figure, in: r.stdout), validated = Self.count(of: figure, in: v.stdout)
            XCTAssertNotNil(imported, "\(figure) missing: \(r)")
            XCTAssertEqual(imported, validated, "\(figure): import says \(imported ?? -1), validate-map \(validated ?? -1)")
        }
        XCTAssertGreaterThan(Self.count(of: "signs", in: v.stdout) ?? 0, 0)
    }

    func testImportInavigateOfAMissingFolderExitsOneNamingIt() throws {
        let missing = directory.appendingPathComponent("no-such-inavigate").path
        let r = try CLI.run(["import-inavigate", missing, "-o", directory.appendingPathComponent("x.json").path])
        r.assertExit(1)
        r.assertStderr(contains: "no-such-inavigate")
    }

    func testImportInavigateToAnUnwritablePlaceExitsOneNamingIt() throws {
        let source = try sharedData("skeri_inavigate")
        let out = directory.appendingPathComponent("no-such-folder/skeri.json").path
        let r = try CLI.run(["import-inavigate", source.path, "-o", out])
        r.assertExit(1)
        r.assertStderr(contains: "wayfinder import-inavigate: ", out)
        XCTAssertFalse(r.stdout.contains("wrote"), "\(r)")
    }

    func testImportOccamWritesABundleThatInspectReads() throws {
        let file = try sharedData("occamlab_invisible_map_arkit").appendingPathComponent("floor_2_straight_uncleaned.json")
        guard FileManager.default.fileExists(atPath: file.path) else { throw XCTSkip("\(file.path) is not present") }
        let out = directory.appendingPathComponent("occam").path
        let r = try CLI.run(["import-occam", file.path, "-o", out, "--json"])
        r.assertExit(0)
        let figures = try XCTUnwrap(try JSONSerialization.jsonObject(with: Data(r.stdout.utf8)) as? [String: Any], "\(r)")
        let frames = try XCTUnwrap(figures["frameCount"] as? Int, "\(r)")
        XCTAssertGreaterThan(frames, 10)
        let i = try CLI.run(["inspect", "--json", out])
        i.assertExit(0)
        let summary = try XCTUnwrap(try JSONSerialization.jsonObject(with: Data(i.stdout.utf8)) as? [String: Any], "\(i)")
        XCTAssertEqual(summary["frameCount"] as? Int, frames)
        XCTAssertEqual(summary["observationCount"] as? Int, figures["sightingCount"] as? Int)
        // A second import onto the same bundle is refused without --overwrite.
        let again = try CLI.run(["import-occam", file.path, "-o", out])
        again.assertExit(1)
    }

    func testRangeOnTheCommittedFixture() throws {
        let fixture = "Tests/Fixtures/range/observations.csv"
        guard FileManager.default.fileExists(atPath: CLI.repo(fixture).path) else { throw XCTSkip("\(fixture) is not present") }
        let dataRows = try String(contentsOf: CLI.repo(fixture), encoding: .utf8).split(separator: "\n")
            .filter { !$0.hasPrefix("#") && !$0.trimmingCharacters(in: .whitespaces).isEmpty }.count - 1
        XCTAssertGreaterThan(dataRows, 0)

        let all = try CLI.run(["range", "--input", fixture])
        all.assertExit(0)
        let lines = all.stdoutLines
        XCTAssertEqual(lines.first, "line,method,range_m,bearing_deg,center_height_above_camera_m,true_range_m,error_pct,status")
        XCTAssertEqual(lines.count - 1, dataRows * 3, "one line per observation and method: \(all)")
        all.assertStderr(contains: "apparent-height: median error")

        // Apparent height is exact for any roll: lines 2-9 are exact projections printed to 0.001 px, later lines
        // carry 1.5 px of corner noise (docs/range-estimation.md; same tolerances as RangeEstimatorCSVTests).
        let one = try CLI.run(["range", "--input", fixture, "--method", "apparent-height"])
        one.assertExit(0)
        let rows = one.stdoutLines.dropFirst().map { $0.split(separator: ",", omittingEmptySubsequences: false).map(String.init) }
        XCTAssertEqual(rows.count, dataRows)
        for row in rows {
            XCTAssertEqual(row.count, 8, "\(row)")
            XCTAssertEqual(row.last, "ok", "\(row)")
            XCTAssertEqual(row[1], "apparent-height")
            let range = try XCTUnwrap(Double(row[2])), truth = try XCTUnwrap(Double(row[5]))
            let exact = (Int(row[0]) ?? 99) <= 9
            XCTAssertEqual(range, truth, accuracy: (exact ? 2e-4 : 0.15) * truth, "line \(row[0])")
        }
    }

    func testRangeOnABadCSVExitsOneNamingFileAndLine() throws {
        let csv = directory.appendingPathComponent("bad.csv")
        let header = "image_width,image_height,fx,fy,cx,cy,pitch_rad,roll_rad,u_tl,v_tl,u_tr,v_tr,u_br,v_br,u_bl,v_bl,sign_height_m"
        let good = "1920,1440,1602,1602,960,720,0.1,0,1056,563,1141,565,1141,620,1056,618,0.21"
        let bad = "1920,1440,1602,1602,960,720,0.1,0,1056,563,1141,565,1141,620,1056,oops,0.21"
        try Data([header, good, bad].joined(separator: "\n").utf8).write(to: csv)
        let r = try CLI.run(["range", "--input", csv.path])
        r.assertExit(1)
        r.assertStderr(contains: "bad.csv:3: ", "v_bl")
        let missing = try CLI.run(["range", "--input", directory.appendingPathComponent("nope.csv").path])
        missing.assertExit(1)
        missing.assertStderr(contains: "nope.csv")
    }

    /// The number before `word` in a "N floors, N walls, ..." summary line.
    private static func count(of word: String, in text: String) -> Int? {
        let tokens = text.split(whereSeparator: { $0 == " " || $0 == "," || $0 == "\n" }).map(String.init)
        guard let i = tokens.firstIndex(of: word), i > 0 else { return nil }
        return Int(tokens[i - 1])
    }
}
