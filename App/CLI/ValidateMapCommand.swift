import Foundation
import Localizer
import Maps

/// `wayfinder validate-map MAP...`: loads each map file with every check of format v1 and prints a one-line
/// summary, or the one error naming the file, the JSON path and the reason.
enum ValidateMapCommand: Subcommand {
    static let name = "validate-map"
    static let summary = "check map files (format v1) and print their size, or the first error"
    static let usage = """
    Usage: wayfinder validate-map MAP [MAP...]

    Loads each MAP (map format v1, docs/map-format.md) with all of its checks and prints
      ok: FILE: N floors, N walls, N signs, N POIs, N nodes
    then, for each floor that a rotation maps onto itself (docs/localizer.md "Symmetric twins"),
      floor F: symmetric under a half turn about (X, Y) (P % of the walls)
    (there the localizer waits until a sign or wall the turn does not map tells each place from its twin),
    or the first error as "FILE: JSONPATH: reason" on stderr. \(MapSpec.usageLine).
    Exit codes: 0 all maps valid, 1 some map invalid, 2 usage.
    """

    static func run(_ arguments: inout ArgumentList) throws -> Int32 {
        let paths = try arguments.positionals()
        guard !paths.isEmpty else { throw CLIError.usage("give at least one map file") }
        var failures = 0
        for path in paths {
            do {
                let building = try MapSpec.resolve(path)
                let c = building.counts
                print("ok: \(path): \(c.floors) floors, \(c.walls) walls, \(c.signs) signs, \(c.pointsOfInterest) POIs, \(c.nodes) nodes")
                do {
                    for line in try symmetryLines(building) { print(line) }
                } catch {
                    FileHandle.standardError.write(Data("warning: \(path): the localizer could not load the map (\(error)): symmetries not checked\n".utf8))
                }
            } catch let e as MapError {
                failures += 1
                // MapError.file is the last path component; print the path as the user typed it.
                FileHandle.standardError.write(Data("error: \(path): \(e.jsonPath): \(e.reason)\n".utf8))
            } catch let e as CLIError {
                failures += 1
                FileHandle.standardError.write(Data("error: \(e.description)\n".utf8))
            }
        }
        if failures > 0 && paths.count > 1 {
            FileHandle.standardError.write(Data("\(failures) of \(paths.count) maps invalid\n".utf8))
        }
        return failures == 0 ? 0 : 1
    }

    /// One line per floor with a rotational symmetry, as the localizer finds it when it loads the map.
    static func symmetryLines(_ building: Building) throws -> [String] {
        let localizer = try ParticleLocalizer(building: building)
        return building.floors.flatMap { floor in
            localizer.floorSymmetries(floorId: floor.id).map { s in
                String(format: "  floor %@: symmetric under %@ about (%.1f, %.1f) (%.0f %% of the walls)", floor.id,
                       s.turnDescription, s.center.x, s.center.y, 100 * s.matchedFraction)
            }
        }
    }
}
