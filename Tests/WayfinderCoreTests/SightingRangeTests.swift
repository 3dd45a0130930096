import Foundation
import XCTest
import Localizer
import SessionFormat
@testable import WayfinderCore

/// The pipeline's sighting range: sightings beyond `maximumSightingRangeMeters` are not given to the localizer,
/// which predicts signs visible 3 range sigmas farther (`signHorizonMeters`), so a far sign that a detector
/// measures just inside the accepted range is explained by the true pose too.
final class SightingRangeTests: XCTestCase {
    func testFarSightingsAreDroppedAndThePredictionReachesThreeSigmasFarther() throws {
        var options = PipelineOptions()
        XCTAssertEqual(options.maximumSightingRangeMeters, 12)
        // 12 m + 3 (0.1 m + 0.12 x 12 m) with the localizer's default range noise.
        XCTAssertEqual(options.signHorizonMeters, 12 + 3 * (options.localizer.rangeSigmaBaseMeters
                                                           + options.localizer.rangeSigmaPerMeter * 12), accuracy: 1e-9)
        XCTAssertEqual(options.signHorizonMeters, 16.62, accuracy: 0.01)
        options.localizer.particleCount = 5000
        let pipeline = try WayfinderPipeline(building: try TestData.office(), options: options)
        func frame(_ t: Double, ranges: [Double]) -> PipelineFrame {
            PipelineFrame(t: t, cameraPose: CameraPose(positionInWorld: (0, 1.4, 0), yawRad: 0, pitchRad: 0, rollRad: -.pi / 2),
                          tracking: .normal, intrinsics: .iPhone8Full,
                          measuredObservations: ranges.map {
                              ObservationRecord(t: t, kind: "exit", rangeMeters: $0, bearingRad: 0, score: 0.9)
                          })
        }
        XCTAssertEqual(pipeline.process(frame(0, ranges: [8, 11.9, 12.5, 30])).sightings.map(\.rangeMeters), [8, 11.9])
        XCTAssertTrue(pipeline.process(frame(0.2, ranges: [13])).sightings.isEmpty)
        options.maximumSightingRangeMeters = 20
        let wider = try WayfinderPipeline(building: try TestData.office(), options: options)
        XCTAssertEqual(wider.process(frame(0, ranges: [13])).sightings.count, 1)
    }
}
