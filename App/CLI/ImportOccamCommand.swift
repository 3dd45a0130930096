import Foundation
import SessionFormat

/// `wayfinder import-occam`: converts an OCCaM Lab InvisibleMap recording (real ARKit walk + AprilTag
/// sightings) into a session bundle.
enum ImportOccamCommand: Subcommand {
    static let name = "import-occam"
    static let summary = "convert an OCCaM InvisibleMap ARKit recording (.json) into a session bundle"
    static let usage = """
    Usage: wayfinder import-occam FILE.json -o BUNDLE [--overwrite] [--json]   (--output BUNDLE also works)

    Reads an OCCaM Lab InvisibleMap recording (pose_data: ARKit camera poses; tag_data: AprilTag sightings;
    see ../shared/data/occamlab_invisible_map_arkit/SOURCE.md) and writes the bundle directory BUNDLE: one
    frame per pose, one observation (kind "landmark", landmarkId = tag id, horizontal range and bearing
    from the camera) per sighting. Refuses a non-empty BUNDLE unless --overwrite. Prints the figures of
    the import (--json: as JSON).
    Exit codes: 0 ok, 1 missing or damaged input, 2 usage.
    """

    static func run(_ arguments: inout ArgumentList) throws -> Int32 {
        var output = try arguments.option("output")
        let overwrite = arguments.flag("overwrite")
        let json = arguments.flag("json")
        var inputs = try arguments.positionals()
        // `-o BUNDLE` (single dash) arrives among the positionals.
        if let i = inputs.firstIndex(of: "-o") {
            guard i + 1 < inputs.count else { throw CLIError.usage("-o needs a value") }
            output = inputs[i + 1]
            inputs.removeSubrange(i...(i + 1))
        }
        guard inputs.count == 1 else { throw CLIError.usage("give exactly one OCCaM .json file") }
        guard let output else { throw CLIError.usage("missing -o BUNDLE") }
        let summary: OccamImporter.Summary
        do {
            summary = try OccamImporter.importWalk(from: URL(fileURLWithPath: inputs[0]),
                                                   to: URL(fileURLWithPath: output), overwrite: overwrite)
        } catch let e as OccamImporter.ImportError {
            throw CLIError.failure(e.description)
        } catch let e as BundleError {
            throw CLIError.failure(e.description)
        }
        if json {
            let encoder = JSONEncoder()
            encoder.outputFormatting = [.prettyPrinted, .sortedKeys, .withoutEscapingSlashes]
            print(String(decoding: try encoder.encode(summary), as: UTF8.self))
        } else {
            let figures = String(format: "%d frames over %.1f s, path %.1f m, %d tag sightings of %d tags",
                                 summary.frameCount, summary.durationSeconds, summary.pathLengthMeters,
                                 summary.sightingCount, summary.distinctTagCount)
            print("\(output): \(figures) (\(summary.skippedSightings) skipped, \(summary.droppedDuplicatePoses) "
                + "duplicate poses dropped), poses \(summary.poseMatrixOrder)")
        }
        return 0
    }
}
