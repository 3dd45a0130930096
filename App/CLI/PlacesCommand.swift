import Foundation
import Maps
import WayfinderCore

/// `wayfinder places MAP`: the places (points of interest) a walk can start or end at, by floor.
enum PlacesCommand: Subcommand {
    static let name = "places"
    static let summary = "list a map's places by floor (the ids and names --from and --to take)"
    static let usage = """
    Usage: wayfinder places MAP [--floor FLOOR] [--search WORDS]

    Prints the places of MAP floor by floor, one per line: id, name, category. --from and --to take the id
    or the name; a name several floors share (an "Elevator" on each floor) must be given by its id.
      --floor FLOOR    only this floor id
      --search WORDS   only places whose name or category holds every word (case-insensitive)
    \(MapSpec.usageLine).
    Exit codes: 0 ok, 1 bad input (map, unknown floor), 2 usage.
    """

    static func run(_ arguments: inout ArgumentList) throws -> Int32 {
        let floorFilter = try arguments.option("floor")
        let search = try arguments.option("search") ?? ""
        let positionals = try arguments.positionals()
        guard positionals.count == 1 else { throw CLIError.usage("expected one MAP (see --help)") }
        let building = try loadMap(positionals[0])
        if let floorFilter, building.floor(id: floorFilter) == nil {
            throw CLIError.failure("\(positionals[0]) has no floor '\(floorFilter)' (floors: \(building.floors.map(\.id).joined(separator: ", ")))")
        }
        let matches = PlaceList(building: building).search(search, floorId: floorFilter)
        let byFloor = Dictionary(grouping: matches, by: \.floorId)
        let idWidth = min(28, matches.map(\.id.count).max() ?? 0)
        var printed = 0
        for floor in building.floors {
            guard let items = byFloor[floor.id], !items.isEmpty else { continue }
            print("Floor \(floor.id) (\(floor.name)): \(items.count) place\(items.count == 1 ? "" : "s")")
            for item in items {
                print("  \(item.id.padding(toLength: max(idWidth, item.id.count), withPad: " ", startingAt: 0))  \(item.name)  [\(item.category)]")
                printed += 1
            }
        }
        if printed == 0 { note("places: no place matches on \(positionals[0])") }
        return 0
    }
}
