import XCTest
import Maps
import SessionFormat
@testable import WayfinderCore

/// Detector scheduling, tracking prompts and place search: the iOS shell's logic, tested on Linux.
final class SessionPoliciesTests: XCTestCase {
    func testSchedulerDropsFramesWhileBusyAndThrottlesWhenHot() {
        var s = DetectorScheduler(baseRateHz: 10)
        // 30 Hz frames for 1 s, detector always finishing at once: 10 detections.
        var accepted = 0
        for i in 0..<30 {
            if s.shouldDetect(t: Double(i) / 30) { accepted += 1; s.detectionFinished() }
        }
        XCTAssertEqual(accepted, 10)
        // Busy detector: nothing more is accepted until it finishes (frames dropped, not queued).
        XCTAssertTrue(s.shouldDetect(t: 2.0))
        XCTAssertFalse(s.shouldDetect(t: 2.5))
        s.detectionFinished()
        XCTAssertTrue(s.shouldDetect(t: 2.6))
        s.detectionFinished()
        s.thermal = .serious
        XCTAssertEqual(s.rateHz, 4, accuracy: 1e-9)
        s.lowPower = true
        XCTAssertEqual(s.rateHz, 2.4, accuracy: 1e-9)
    }

    func testTrackingPromptsArePersistentAndRateLimited() {
        var p = TrackingPromptPolicy()
        var spoken: [(Double, String)] = []
        // 30 s of excessive motion at 10 Hz.
        for i in 0..<300 {
            let t = Double(i) / 10
            if let s = p.update(t: t, state: .limited, reason: .excessiveMotion) { spoken.append((t, s)) }
        }
        XCTAssertEqual(spoken.map(\.1), ["Slow down", "Slow down", "Slow down"])
        XCTAssertEqual(spoken[0].0, 1.5, accuracy: 0.01)
        XCTAssertEqual(spoken[1].0 - spoken[0].0, 12, accuracy: 0.11)
        // A brief glitch stays silent.
        var q = TrackingPromptPolicy()
        XCTAssertNil(q.update(t: 0, state: .limited, reason: .insufficientFeatures))
        XCTAssertNil(q.update(t: 1, state: .normal, reason: nil))
        XCTAssertNil(q.update(t: 2, state: .limited, reason: .insufficientFeatures))
        // Covered camera wins over the tracking reason.
        XCTAssertEqual(TrackingPromptPolicy.prompt(for: .limited, reason: .insufficientFeatures, meanLuma: 2), "The camera is covered")
    }

    func testPlaceSearch() {
        let floor = Floor(id: "1", name: "Floor 1", elevationMeters: 0, walls: [],
                          pointsOfInterest: [PointOfInterest(id: "r1", name: "Café Lounge", category: "kitchen", position: Point2(0, 0), behindDoor: false),
                                             PointOfInterest(id: "r2", name: "Room 101", category: "office", position: Point2(1, 0), behindDoor: true)])
        let list = PlaceList(building: Building(id: "b", name: "B", floors: [floor], graph: NavigationGraph(nodes: [], edges: [])))
        XCTAssertEqual(list.search("cafe").map(\.id), ["r1"])
        XCTAssertEqual(list.search("office 101").map(\.id), ["r2"])
        XCTAssertEqual(list.search("").count, 2)
        XCTAssertEqual(list.items[1].accessibilityLabel, "Room 101, office, Floor 1")
    }
}
