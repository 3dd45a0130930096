import Foundation
import Maps
import Simulation
import WayfinderCore

/// The one way every command names a map (`--map MAP`, `validate-map MAP`, `places MAP`):
/// - `office`: the bundled Wayfinder Office (`bundled:office`, the older spelling, too);
/// - `skeri` or `skeri:FLOOR`: the Smith-Kettlewell building imported from the shared iNavigate data
///   (`$WAYFINDER_SHARED_DATA` or ../shared/data, `skeri_inavigate/`); FLOOR must be one of its floor ids;
/// - anything else: a path to a map-v1 JSON file (write `./office` for a file of that name).
enum MapSpec {
    /// One line for the usage texts.
    static let usageLine = "MAP is `office` (the bundled office), `skeri` or `skeri:FLOOR` (shared SKERI data) or a map-v1 JSON file"

    /// Loads the map named by `spec`. Throws the map reader's own error (a `MapError` naming the file, the
    /// JSON path and the reason) for a map file, or a `CLIError` for a name that cannot be resolved.
    static func resolve(_ spec: String) throws -> Building {
        if spec == "office" || spec == "bundled:office" { return try BundledMaps.office() }
        if spec == "skeri" || spec.hasPrefix("skeri:") {
            let building: Building
            do { building = try ScenarioMaps.load("skeri") } catch { throw CLIError.failure("\(spec): \(error)") }
            if let floor = ScenarioMaps.skeriFloor(spec), building.floor(id: floor) == nil {
                throw CLIError.failure("\(spec): SKERI has no floor '\(floor)' (floors: \(building.floors.map(\.id).joined(separator: ", ")))")
            }
            return building
        }
        // Nothing at all at this path (lstat: a link loop or a dangling link is there, and the map reader
        // names its problem): say what a map can be.
        var info = stat()
        if lstat(spec, &info) != 0 && errno == ENOENT {
            throw CLIError.failure("\(spec): no such file (\(usageLine))")
        }
        return try MapLoader.load(contentsOf: URL(fileURLWithPath: spec))
    }

    /// The floor a `skeri:FLOOR` spec names, to start on when nothing else says.
    static func floor(of spec: String) -> String? { ScenarioMaps.skeriFloor(spec) }
}

/// Loads the map named by `spec` (see `MapSpec`), turning every error into a CLI failure naming the map.
func loadMap(_ spec: String) throws -> Building {
    do { return try MapSpec.resolve(spec) } catch let e as CLIError { throw e } catch {
        throw CLIError.failure("\(error)")
    }
}

/// Resolves a place given on the command line (`--from`, `--to`) to its point-of-interest id: an exact id,
/// else a name (case-insensitive). A name several places share (an "Elevator" on each floor) is an error
/// that lists them with their ids and floors, never a silent pick; so is a name no place has.
func resolvePlace(_ key: String, flag: String, in building: Building, mapSpec: String) throws -> String {
    for floor in building.floors where floor.pointOfInterest(id: key) != nil { return key }
    // A route-graph node id (as the committed scenario definitions name their start and end).
    if building.node(id: key) != nil { return key }
    func nameKey(_ s: String) -> String { s.trimmingCharacters(in: .whitespacesAndNewlines).lowercased() }
    let named = building.floors.flatMap { floor in
        floor.pointsOfInterest.filter { nameKey($0.name) == nameKey(key) }.map { (poi: $0, floor: floor) }
    }
    if named.count == 1 { return named[0].poi.id }
    if named.isEmpty {
        // Places whose name or category holds every word of the key ("Elevator" -> each floor's "Elevator lobby").
        let similar = PlaceList(building: building).search(key)
        let floorOrder = Dictionary(building.floors.enumerated().map { ($1.id, $0) }, uniquingKeysWith: { a, _ in a })
        let shown = similar.sorted { (floorOrder[$0.floorId] ?? 0, $0.name) < (floorOrder[$1.floorId] ?? 0, $1.name) }.prefix(8)
        let hint = shown.isEmpty ? "" : "; places like it: " + shown.map { "\($0.id) (\($0.name), floor \($0.floorId))" }.joined(separator: ", ")
            + (similar.count > shown.count ? ", ... \(similar.count - shown.count) more" : "")
        throw CLIError.failure("\(flag) '\(key)': no place has this id or name on \(mapSpec)\(hint) (see 'wayfinder places \(mapSpec)')")
    }
    let list = named.map { "\($0.poi.id) (floor \($0.floor.id), \($0.floor.name))" }.joined(separator: ", ")
    throw CLIError.failure("\(flag) '\(key)' names \(named.count) places: \(list); give one of these ids")
}
