import XCTest
import SessionFormat
@testable import WayfinderCore

/// `WayfinderPipeline`'s handling of ARKit's tracking seams.
final class WayfinderPipelineTests: XCTestCase {
    private func frame(_ t: Double, x: Double, yawRad: Double, _ tracking: TrackingState,
                       _ reason: TrackingReason? = nil) -> PipelineFrame {
        PipelineFrame(t: t, cameraPose: CameraPose(positionInWorld: (x, 1.4, 0), yawRad: yawRad, pitchRad: 0, rollRad: -.pi / 2),
                      tracking: tracking, trackingReason: reason, intrinsics: .iPhone8Full)
    }

    private func restartWarnings(_ update: PipelineUpdate) -> [String] {
        update.warnings.filter { $0.contains("world tracking restarted") }
    }

    /// ARKit initializing again after it tracked (world tracking restarted: a new VIO origin, possibly turned) is a
    /// seam the motion update must not span: the localizer is told the VIO frame is new, once per restart, whether
    /// notAvailable frames came between or not. The session's first initializing frames are not a restart.
    func testInitializingAgainAfterTrackingStartsANewVioFrame() throws {
        var o = PipelineOptions()
        o.localizer.particleCount = 2000
        o.localizer.minParticles = 1000
        let pipeline = try WayfinderPipeline(building: try TestData.office(), options: o)
        var restarts: [Double] = []
        func run(_ f: PipelineFrame) {
            let update = pipeline.process(f)
            XCTAssertLessThanOrEqual(restartWarnings(update).count, 1)
            if !restartWarnings(update).isEmpty { restarts.append(f.t) }
            XCTAssertTrue(update.estimate.positionInMap.x.isFinite && update.estimate.positionInMap.y.isFinite)
        }
        for k in 0..<10 { run(frame(Double(k) / 10, x: 0, yawRad: 0, .limited, .initializing)) }
        for k in 10..<30 { run(frame(Double(k) / 10, x: 0.1 * Double(k - 10), yawRad: 0, .normal)) }
        // Restarted: the new origin is where the camera is, turned a quarter.
        for k in 30..<40 { run(frame(Double(k) / 10, x: 0.05 * Double(k - 30), yawRad: .pi / 2, .limited, .initializing)) }
        for k in 40..<50 { run(frame(Double(k) / 10, x: 0.5 + 0.1 * Double(k - 40), yawRad: .pi / 2, .normal)) }
        // Restarted through notAvailable frames (as ARKit reports a reset run), then tracking normal again.
        run(frame(5.0, x: 1.5, yawRad: .pi / 2, .notAvailable))
        for k in 51..<60 { run(frame(Double(k) / 10, x: 0, yawRad: 0, .limited, .initializing)) }
        for k in 60..<70 { run(frame(Double(k) / 10, x: 0.1 * Double(k - 60), yawRad: 0, .normal)) }
        // A tracking loss that returns without initializing (ARKit kept or relocalized its frame) is no restart.
        run(frame(7.0, x: 1.0, yawRad: 0, .notAvailable))
        for k in 71..<80 { run(frame(Double(k) / 10, x: 1.0, yawRad: 0, .limited, .relocalizing)) }
        XCTAssertEqual(restarts.count, 2)
        XCTAssertEqual(restarts.first ?? -1, 3.0, accuracy: 1e-9)
        XCTAssertEqual(restarts.last ?? -1, 5.1, accuracy: 1e-9)
    }
}
