import Foundation
import Maps

/// The building as it truly is, against the map the localizer reads: each sign slid along its wall and its face
/// scaled by the survey's errors (`SurveyParameters`). The simulated detector sees these signs (and the renderer
/// draws them); the recorded bundle names the map, so a replay localizes against the map as surveyed.
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
    /// sign in map order, a standard normal for the slide along the wall (times
    /// `signAlongWallSigmaMeters`, perpendicular to the sign's facing) and one for the log of the size factor
    /// (times `signSizeLogSigma`). Both are drawn for every sign whatever the settings, so one setting's draws do
    /// not depend on the other. With both settings zero the floors are returned unchanged.
    public init(floors: [String: Floor], parameters p: SurveyParameters, rng: inout SeededRandom) {
        self.floors = floors
        self.rangeFactors = [:]
        guard p.signAlongWallSigmaMeters > 0 || p.signSizeLogSigma > 0 else { return }
        for floorId in floors.keys.sorted() {
            guard var floor = floors[floorId] else { continue }
            var factors: [String: Double] = [:]
            for i in floor.signs.indices {
                let slide = p.signAlongWallSigmaMeters * rng.normal()
                let k = exp(p.signSizeLogSigma * rng.normal())
                var sign = floor.signs[i]
                let n = hypot(sign.facing.x, sign.facing.y)
                if n > 1e-9 {
                    // Along the wall: the facing turned a quarter.
                    let tx = -sign.facing.y / n, ty = sign.facing.x / n
                    sign.position = Point2(sign.position.x + slide * tx, sign.position.y + slide * ty)
                }
                sign.widthMeters *= k
                sign.heightMeters *= k
                factors[sign.id] = 1 / k
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
