import Foundation
import Maps

/// `wayfinder import-inavigate DIR -o OUT.json`: converts the reference iNavigate app's maps (e.g. the
/// Smith-Kettlewell floors in ../shared/data/skeri_inavigate) to map format v1.
enum ImportInavigateCommand: Subcommand {
    static let name = "import-inavigate"
    static let summary = "convert iNavigate maps (info.yml, wall BMPs, Exit-sign survey, navgraph) to format v1"
    static let usage = """
    Usage: wayfinder import-inavigate DIR -o OUT.json [--floor-height M] [--snap M]

    Reads DIR/info.yml (or DIR/floors/info.yml), each floor's wall mask BMP and mapFeatures yml, and
    navgraph.json; writes a validated format-v1 map to OUT.json and prints per-floor figures.
      -o, --output FILE   map file to write (required)
      --floor-height M    floor-to-floor height for elevations, meters (default 4.0; not in the source)
      --snap M            move a surveyed sign onto a wall face within M meters (default 0.5)
    Exit codes: 0 ok, 1 missing/damaged input or invalid result, 2 usage.
    """

    static func run(_ arguments: inout ArgumentList) throws -> Int32 {
        var output = try arguments.option("output")
        if output == nil { output = try arguments.option("o") }
        var options = InavigateImporter.Options()
        if let h = try arguments.doubleOption("floor-height") {
            guard h > 0 else { throw CLIError.usage("--floor-height must be positive") }
            options.floorHeightMeters = h
        }
        if let s = try arguments.doubleOption("snap") {
            guard s >= 0 else { throw CLIError.usage("--snap must not be negative") }
            options.maximumSnapDistanceMeters = s
        }
        // `-o FILE` (single dash) is not an ArgumentList option form: take it from the positionals.
        var rest = try arguments.positionals()
        if let i = rest.firstIndex(of: "-o") {
            guard i + 1 < rest.count else { throw CLIError.usage("-o needs a value") }
            output = rest[i + 1]
            rest.removeSubrange(i...(i + 1))
        }
        guard rest.count == 1, let dir = rest.first else { throw CLIError.usage("give exactly one iNavigate map folder") }
        guard let out = output else { throw CLIError.usage("missing -o OUT.json") }
        do {
            let (building, report) = try InavigateImporter.importBuilding(from: URL(fileURLWithPath: dir), options: options)
            do { try MapWriter.write(building, to: URL(fileURLWithPath: out)) } catch let e as MapError { throw e } catch {
                throw CLIError.failure("cannot write \(out): \(error.localizedDescription)")
            }
            for r in report {
                let wallSigns = building.floor(id: r.floorId)?.signs.filter { $0.placement == .wall }.count ?? 0
                let moved = r.signAdjustmentsMeters.max() ?? 0
                note("floor \(r.floorId): \(r.walls) walls, \(r.signs) signs (\(wallSigns) on walls, \(r.signs - wallSigns) projecting; largest move \(String(format: "%.2f", moved)) m), \(r.pointsOfInterest) POIs, \(r.nodes) nodes")
            }
            let c = building.counts
            print("wrote \(out): \(c.floors) floors, \(c.walls) walls, \(c.signs) signs, \(c.pointsOfInterest) POIs, \(c.nodes) nodes, \(c.edges) edges")
            return 0
        } catch let e as InavigateImportError {
            throw CLIError.failure(e.description)
        } catch let e as MapError {
            throw CLIError.failure("converted map is invalid: \(e.description)")
        }
    }
}
