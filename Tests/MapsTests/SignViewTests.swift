import Foundation
import XCTest
@testable import Maps

/// The geometry of seeing a sign (Maps/Sources/SignView.swift), shared by the simulator and ExpectedSignKinds.
final class SignViewTests: XCTestCase {
    /// A sign at the origin whose face looks along +x.
    private func sign(doubleSided: Bool = false, facing: Point2 = Point2(2, 0)) -> Sign {
        Sign(id: "s", kind: "exit", position: Point2(0, 0), facing: facing, widthMeters: 0.33, heightMeters: 0.21,
             mountingHeightMeters: nil, doubleSided: doubleSided)
    }

    /// Offset (sign minus viewer) and distance of a viewer `r` meters away at `angleDeg` from the face normal.
    private func viewer(_ r: Double, _ angleDeg: Double) -> (dx: Double, dy: Double, r: Double) {
        let a = angleDeg * Double.pi / 180
        return (-r * cos(a), -r * sin(a), r)
    }

    func testTheFaceIsSeenWithinItsViewAngleAndFromBehindOnlyWhenDoubleSided() {
        for (angle, seen) in [(0.0, true), (59.0, true), (-59.0, true), (61.0, false), (180.0, false)] {
            let v = viewer(3, angle)
            XCTAssertEqual(sign().faceIsTurned(towardsViewerAtOffset: v.dx, v.dy, distanceMeters: v.r, maxViewAngleDeg: 60),
                           seen, "\(angle) deg")
        }
        let behind = viewer(3, 170)
        XCTAssertTrue(sign(doubleSided: true).faceIsTurned(towardsViewerAtOffset: behind.dx, behind.dy,
                                                            distanceMeters: behind.r, maxViewAngleDeg: 60))
        // A sign without a facing is seen from nowhere within less than 90 degrees.
        let front = viewer(3, 0)
        XCTAssertFalse(sign(facing: Point2(0, 0)).faceIsTurned(towardsViewerAtOffset: front.dx, front.dy,
                                                               distanceMeters: front.r, maxViewAngleDeg: 60))
    }

    func testTheLineOfSightEndsFiveCentimetresInFrontOfTheSignTowardsTheViewer() {
        let v = viewer(2, 90)  // viewer at (0, 2): offset (0, -2)
        let end = sign().lineOfSightEnd(viewerOffset: v.dx, v.dy, distanceMeters: v.r)
        XCTAssertEqual(end.x, 0, accuracy: 1e-12)
        XCTAssertEqual(end.y, 0.05, accuracy: 1e-12)
    }
}
