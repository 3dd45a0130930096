import Maps

/// A simulated survey of room-number placards, for the study of what identifying signs do to localization
/// (issue 16 section 3; `wayfinder eval --survey-placards`, docs/benchmarks.md "Placards"). Importers leave
/// placards out (no source surveys them), so the study adds one beside every room-like point of interest:
/// on the wall nearest the entrance (ADA 703.4 puts the placard on the wall beside the door), facing the
/// entrance, its legend the place's id (unique in the building, as a room number is), with the kind's
/// recognition limits in the map's catalogue.
public enum PlacardSurvey {
    /// The placard kind: a 0.15 m square plate with 25 mm digits, read by text recognition from at most 2.5 m
    /// and 50 degrees off square (docs/map-format.md, `maxRangeMeters`), centre 1.5 m above the floor.
    public static let placardKind = SignKindSpec.roomPlacard
    /// Bottom edge of the plate above the floor, meters (ADA: the text 1.22-1.52 m above the floor).
    public static let mountingHeightMeters = placardKind.mountingHeightMeters!
    /// Categories of points of interest that get no placard: their signs are pictograms (elevator, stairs)
    /// or Exit signs, not room numbers.
    public static let categoriesWithoutPlacard: Set<String> = ["elevator", "stairs", "exit"]

    /// `building` with a placard beside every room-like point of interest that has none within 1.5 m (see the type) and the placard
    /// kind added to an explicit catalogue (the map's, or the derived one). A place whose nearest wall is
    /// more than 1.5 m away gets none (it is in an open hall).
    public static func addingPlacards(to building: Building) -> Building {
        var b = building
        var kinds = building.signCatalogue.kinds.filter { $0.kind != placardKind.kind }
        kinds.append(placardKind)
        b.signKinds = kinds
        for fi in b.floors.indices {
            let floor = b.floors[fi]
            for poi in floor.pointsOfInterest where !categoriesWithoutPlacard.contains(poi.category) {
                // A place the map already gives a placard (the bundled office's rooms) keeps it alone.
                if floor.signs.contains(where: { $0.kind == placardKind.kind && $0.position.distance(to: poi.position) <= 1.5 }) {
                    continue
                }
                guard let nearest = floor.nearestWall(to: poi.position), nearest.distanceMeters <= 1.5,
                      nearest.distanceMeters > 1e-6 else { continue }
                let onWall = floor.walls[nearest.index].closestPoint(to: poi.position)
                let facing = Point2((poi.position.x - onWall.x) / nearest.distanceMeters,
                                    (poi.position.y - onWall.y) / nearest.distanceMeters)
                var sign = Sign(id: "placard-\(poi.id)", kind: placardKind.kind,
                                position: Point2(onWall.x + 0.01 * facing.x, onWall.y + 0.01 * facing.y), facing: facing,
                                widthMeters: placardKind.widthMeters, heightMeters: placardKind.heightMeters,
                                mountingHeightMeters: mountingHeightMeters)
                sign.text = poi.id
                b.floors[fi].signs.append(sign)
            }
        }
        return b
    }
}
