import Foundation
import XCTest
import Navigation
import Localizer
import SessionFormat
@testable import WayfinderCore

/// ARPlaneAnchor numbers -> PlaneRecord -> localizer observation; the pipeline's anchor table (VIO resets)
/// and its `usePlanes` switch.
final class PlaneConversionTests: XCTestCase {
    // Anchor at (3, 1.2, -4): local x along world -z (horizontal), local y (the normal) along world +x,
    // local z along world -y (vertical).
    private let columns: [[Float]] = [[0, 0, -1, 0], [1, 0, 0, 0], [0, -1, 0, 0], [3, 1.2, -4, 1]]

    private func record(rotation: Float = 0, event: PlaneEvent = .add) -> PlaneRecord? {
        PlaneConversion.record(t: 2, anchorId: "A", event: event, vertical: true, transformColumns: columns,
                               centerLocal: [0.5, 0, 0], extentWidth: 2, extentHeight: 1.5, rotationOnYAxisRad: rotation,
                               classification: nil)
    }

    func testAnchorFieldsBecomeAWorldCenterNormalAndHorizontalWidth() throws {
        let r = try XCTUnwrap(record())
        XCTAssertNil(r.validationProblem())
        let c = try XCTUnwrap(r.centerInWorld)
        XCTAssertEqual(c[0], 3, accuracy: 1e-6); XCTAssertEqual(c[1], 1.2, accuracy: 1e-6); XCTAssertEqual(c[2], -4.5, accuracy: 1e-6)
        XCTAssertEqual(r.normalInWorld!, [1, 0, 0])
        XCTAssertEqual(r.widthMeters!, 2, accuracy: 1e-6)
        XCTAssertEqual(r.heightMeters!, 1.5, accuracy: 1e-6)
        // Turned a quarter about the normal, the extent's height is what lies along the floor.
        let turned = try XCTUnwrap(record(rotation: .pi / 2))
        XCTAssertEqual(turned.widthMeters!, 1.5, accuracy: 1e-5)
        XCTAssertEqual(turned.heightMeters!, 2, accuracy: 1e-5)
        // On the VIO plane: center (3, 4.5), normal toward VIO east (yaw 0).
        let o = try XCTUnwrap(PlaneConversion.observation(of: r))
        XCTAssertEqual(o.centerEast, 3, accuracy: 1e-6); XCTAssertEqual(o.centerNorth, 4.5, accuracy: 1e-6)
        XCTAssertEqual(o.normalYawRad, 0, accuracy: 1e-9)
        XCTAssertEqual(o.anchorId, PlaneObservation.anchorId(for: "A"))
        XCTAssertNotEqual(PlaneObservation.anchorId(for: "A"), PlaneObservation.anchorId(for: "B"))
    }

    func testNonFiniteAnchorsAreNotForwardedAndRemovesCarryNoPose() throws {
        var bad = columns
        bad[3][0] = .nan
        XCTAssertNil(PlaneConversion.record(t: 2, anchorId: "A", event: .update, vertical: true, transformColumns: bad,
                                            centerLocal: [0, 0, 0], extentWidth: 1, extentHeight: 1, rotationOnYAxisRad: 0,
                                            classification: nil))
        XCTAssertNil(PlaneConversion.record(t: 2, anchorId: "A", event: .update, vertical: true, transformColumns: columns,
                                            centerLocal: [0, 0, 0], extentWidth: .infinity, extentHeight: 1, rotationOnYAxisRad: 0,
                                            classification: nil))
        let removed = try XCTUnwrap(record(event: .remove))
        XCTAssertEqual(removed.event, .remove)
        XCTAssertNil(removed.centerInWorld)
        XCTAssertNil(PlaneConversion.observation(of: removed))
    }

    func testAnchorTableFollowsEventsAndDropsEverythingOnAVIOReset() throws {
        var table = PlaneAnchorTable()
        let a = try XCTUnwrap(record())
        var b = a; b.anchorId = "B"
        var floor = a; floor.anchorId = "F"; floor.alignment = .horizontal
        table.observe(tracking: .normal, reason: nil)
        table.apply(a); table.apply(b); table.apply(floor)
        XCTAssertEqual(table.anchors.keys.sorted(), ["A", "B"])
        table.apply(PlaneRecord(t: 3, anchorId: "B", event: .remove))
        XCTAssertEqual(table.observations.count, 1)
        table.observe(tracking: .limited, reason: .relocalizing)
        XCTAssertTrue(table.anchors.isEmpty)
        table.apply(b)   // an update arriving during the reset spell is not trusted
        XCTAssertTrue(table.anchors.isEmpty)
        table.observe(tracking: .normal, reason: nil)
        table.apply(b)
        XCTAssertEqual(table.anchors.keys.sorted(), ["B"])
        table.observe(tracking: .limited, reason: .excessiveMotion)   // not a reset
        XCTAssertEqual(table.anchors.count, 1)
    }

    /// An anchor seen on floor 4 is not scored after an elevator ride to floor 3 (the barometer reads 3.9 m
    /// lower), is scored again when ARKit updates it there, and within the barometer's noise nothing changes.
    /// Without readings, nothing is held back (old recordings).
    func testAnchorsFromAnotherFloorAreNotScored() throws {
        var table = PlaneAnchorTable()
        let a = try XCTUnwrap(record())
        var b = a; b.anchorId = "B"
        table.observe(tracking: .normal, reason: nil)
        table.apply(b)   // before any barometer reading: altitude unknown, always scored
        table.observe(altitudeMeters: 0.1)
        table.apply(a)
        table.observe(altitudeMeters: -0.3)   // noise
        XCTAssertEqual(table.observations.count, 2)
        table.observe(altitudeMeters: -3.9)   // one floor down
        XCTAssertEqual(table.observations.map(\.anchorId), [PlaneObservation.anchorId(for: "B")])
        table.observe(altitudeMeters: .nan)   // ignored: the last finite reading stays
        XCTAssertEqual(table.observations.count, 1)
        table.apply(a)   // ARKit re-estimates it on this floor
        XCTAssertEqual(table.observations.count, 2)
        table.observe(altitudeMeters: 0.0)   // back up: now it belongs to the lower floor
        XCTAssertEqual(table.observations.count, 1)
    }
    /// A plane seen by ARKit becomes a wall in the traveler's own frame at the camera's pose: a camera at world
    /// (1, 1.4, -2) facing VIO north (yaw pi/2, world -z) and a 2 m wide plane 3 m further north (world z -5),
    /// its normal pointing back at the camera, is a wall 3 m ahead from 1 m right to 1 m left; turned to face
    /// VIO east, the same plane is 3 m to the left.
    func testAPlaneBecomesAWallInTheTravelersFrame() throws {
        let plane = PlaneObservation(anchorId: 1, centerEast: 1, centerNorth: 5, normalYawRad: -.pi / 2, widthMeters: 2)
        let north = CameraPose(positionInWorld: (1, 1.4, -2), yawRad: .pi / 2, pitchRad: 0.1, rollRad: -.pi / 2)
        let ahead = try XCTUnwrap(PlaneConversion.perceivedWalls([plane], at: north).first)
        XCTAssertEqual(PerceivedWall.freeDistance([ahead], turnRad: 0, far: 11), 3, accuracy: 1e-9)
        XCTAssertEqual(min(ahead.from.y, ahead.to.y), -1, accuracy: 1e-9)
        XCTAssertEqual(max(ahead.from.y, ahead.to.y), 1, accuracy: 1e-9)
        let east = CameraPose(positionInWorld: (1, 1.4, -2), yawRad: 0, pitchRad: 0, rollRad: -.pi / 2)
        let left = try XCTUnwrap(PlaneConversion.perceivedWalls([plane], at: east).first)
        XCTAssertEqual(PerceivedWall.freeDistance([left], turnRad: .pi / 2, far: 11), 3, accuracy: 1e-9)
        XCTAssertEqual(PerceivedWall.freeDistance([left], turnRad: 0, far: 11), 11)
        var narrow = plane; narrow.widthMeters = 0
        XCTAssertTrue(PlaneConversion.perceivedWalls([narrow], at: north).isEmpty)
    }

    /// The switch: with planes on, a plane the core rejects (non-finite) surfaces as a frame warning; with
    /// `usePlanes` off the pipeline does not even look at plane events.
    func testUsePlanesSwitch() throws {
        let building = try TestData.office()
        let frame0 = PipelineFrame(t: 0, cameraPose: CameraPose(positionInWorld: (0, 1.4, 0), yawRad: 0, pitchRad: 0, rollRad: -.pi / 2),
                                   tracking: .normal, intrinsics: .iPhone8Full)
        var frame1 = frame0
        frame1.t = 0.6
        var weird = try XCTUnwrap(record())
        weird.t = 0.5
        weird.widthMeters = .nan
        for use in [true, false] {
            var o = PipelineOptions()
            o.localizer.particleCount = 2000
            o.localizer.minParticles = 1000
            o.usePlanes = use
            let pipeline = try WayfinderPipeline(building: building, options: o)
            _ = pipeline.process(frame0)
            pipeline.ingest(planes: [weird])
            let update = pipeline.process(frame1)
            XCTAssertEqual(update.warnings.contains { $0.contains("planes:") && $0.contains("non-finite") }, use, "\(update.warnings)")
        }
    }
}
