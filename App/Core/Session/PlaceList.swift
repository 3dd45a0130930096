import Foundation
import Maps

/// One choosable place in the start/destination pickers.
public struct PlaceItem: Hashable, Sendable, Identifiable {
    /// Point-of-interest id.
    public var id: String
    /// Spoken and shown name.
    public var name: String
    /// Category ("restroom", "office", ...).
    public var category: String
    /// Floor id.
    public var floorId: String
    /// Floor name.
    public var floorName: String
    /// VoiceOver label: name, category and floor, so nothing is conveyed only by layout.
    public var accessibilityLabel: String { "\(name), \(category), \(floorName)" }
}

/// The searchable list of labelled places of a building, for the VoiceOver-first pickers.
public struct PlaceList: Sendable {
    /// All places, sorted by floor then name.
    public let items: [PlaceItem]

    /// Lists the building's points of interest.
    public init(building: Building) {
        items = building.floors.flatMap { floor in
            floor.pointsOfInterest.map { PlaceItem(id: $0.id, name: $0.name, category: $0.category, floorId: floor.id, floorName: floor.name) }
        }.sorted { ($0.floorName, $0.name.lowercased()) < ($1.floorName, $1.name.lowercased()) }
    }

    /// Places matching `query` (case- and diacritic-insensitive, every word must appear in the name or
    /// category), optionally on one floor. An empty query lists everything.
    public func search(_ query: String, floorId: String? = nil) -> [PlaceItem] {
        let words = query.folding(options: [.caseInsensitive, .diacriticInsensitive], locale: nil)
            .split(whereSeparator: { $0.isWhitespace }).map(String.init)
        return items.filter { item in
            if let floorId, item.floorId != floorId { return false }
            let hay = "\(item.name) \(item.category)".folding(options: [.caseInsensitive, .diacriticInsensitive], locale: nil)
            return words.allSatisfy { hay.contains($0) }
        }
    }
}
