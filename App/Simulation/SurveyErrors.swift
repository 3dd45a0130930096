import Foundation
import Maps

/// The building as it truly is, against the map the localizer reads: each sign slid along its wall and its face
/// scaled by the survey's errors (`SurveyParameters`). The simulated detector sees these signs (and the renderer
/// draws them); the recorded bundle names the map, so a replay localizes against the map as surveyed. The walls'
/// offsets (`SurveyParameters.wallOffsetSigmaMeters`) are drawn by PlaneSimulator from the same stream, after these.
///
/// Why: every other noise model of the simulator takes the map for the truth. A real map's Exit signs were placed
/// from a floor plan or by hand (the SKERI maps' positions are snapped to the nearest wall by the importer, up to
/// `Sign.positionAdjustmentMeters`), and one building can mix sign models of different sizes; a localizer tuned
/// on a map that is exactly right can be confidently wrong on a real one. Hand-written: a few lines of geometry.
public struct SurveyErrors: Sendable, Equatable {
    /// The true floors by id: the map's, with each sign moved and resized.
    public var floors: [String: Floor]
    /// Per floor id and sign id, the factor the detector's range of that sign reads against the true range
    /// (1 / k for a face k times the catalogue's size; 1 where the size is as surveyed).
    public var rangeFactors: [String: [String: Double]]

    /// Draws the survey's errors for `floors` (the map's floors by id) from `rng`: per floor in id order and per
    /// physical sign (map signs at one position, e.g. the two faces of a sign hung across a corridor, are one sign
    /// and move together) in map order, a standard normal for the slide (times `signAlongWallSigmaMeters`) and one
    /// for the log of the size factor (times `signSizeLogSigma`). A sign flat on a wall slides along that wall,
    /// perpendicular to its facing; a projecting one (flag-mounted, ceiling-hung) along the corridor it hangs
    /// across, i.e. along its facing, so neither passes into a wall. Both numbers are drawn for every sign whatever
    /// the settings, so one setting's draws do not depend on the other. With both settings zero the floors are
    /// returned unchanged.
    public init(floors: [String: Floor], parameters p: SurveyParameters, rng: inout SeededRandom) {
        self.floors = floors
        self.rangeFactors = [:]
        guard p.signAlongWallSigmaMeters > 0 || p.signSizeLogSigma > 0 else { return }
        for floorId in floors.keys.sorted() {
            guard var floor = floors[floorId] else { continue }
            var factors: [String: Double] = [:]
            // One draw per physical sign, keyed by its surveyed position to the millimetre.
            var drawn: [String: (slide: Double, k: Double)] = [:]
            for i in floor.signs.indices {
                var sign = floor.signs[i]
                let key = String(format: "%.3f,%.3f", sign.position.x, sign.position.y)
                let draw: (slide: Double, k: Double)
                if let d = drawn[key] {
                    draw = d
                } else {
                    draw = (p.signAlongWallSigmaMeters * rng.normal(), exp(p.signSizeLogSigma * rng.normal()))
                    drawn[key] = draw
                }
                let n = hypot(sign.facing.x, sign.facing.y)
                if n > 1e-9 {
                    let fx = sign.facing.x / n, fy = sign.facing.y / n
                    // Along the wall: the facing turned a quarter; a projecting sign along its facing.
                    let (tx, ty) = sign.placement == .projecting ? (fx, fy) : (-fy, fx)
                    // The two faces of one projecting sign face opposite ways: one direction for both.
                    let flip = sign.placement == .projecting && (tx < 0 || (tx == 0 && ty < 0)) ? -1.0 : 1.0
                    sign.position = Point2(sign.position.x + flip * draw.slide * tx, sign.position.y + flip * draw.slide * ty)
                }
                sign.widthMeters *= draw.k
                sign.heightMeters *= draw.k
                factors[sign.id] = 1 / draw.k
                floor.signs[i] = sign
            }
            self.floors[floorId] = floor
            rangeFactors[floorId] = factors
        }
    }

    /// The factor the detector's range of sign `signId` on floor `floorId` reads against its true range (1 when
    /// the sign was not resized).
    public func rangeFactor(floorId: String, signId: String) -> Double {
        rangeFactors[floorId]?[signId] ?? 1
    }
}
