import XCTest
@testable import Simulation

final class SeededRandomTests: XCTestCase {
    func testSameSeedSameStreamAndStreamsDiffer() {
        var a = SeededRandom(seed: 42, stream: 1), b = SeededRandom(seed: 42, stream: 1), c = SeededRandom(seed: 42, stream: 2)
        let xa = (0..<100).map { _ in a.next() }, xb = (0..<100).map { _ in b.next() }, xc = (0..<100).map { _ in c.next() }
        XCTAssertEqual(xa, xb)
        XCTAssertNotEqual(xa, xc)
    }

    func testUniformAndNormalMoments() {
        var r = SeededRandom(seed: 7)
        let n = 200_000
        let u = (0..<n).map { _ in r.uniform() }
        XCTAssertEqual(u.reduce(0, +) / Double(n), 0.5, accuracy: 0.005)
        XCTAssertTrue(u.allSatisfy { $0 >= 0 && $0 < 1 })
        let z = (0..<n).map { _ in r.normal() }
        let mean = z.reduce(0, +) / Double(n)
        let variance = z.map { ($0 - mean) * ($0 - mean) }.reduce(0, +) / Double(n - 1)
        XCTAssertEqual(mean, 0, accuracy: 0.01)
        XCTAssertEqual(variance, 1, accuracy: 0.015)
        // Tail mass beyond 2 sigma: 4.55 %.
        XCTAssertEqual(Double(z.filter { abs($0) > 2 }.count) / Double(n), 0.0455, accuracy: 0.003)
    }

    func testOrnsteinUhlenbeckStationarySpread() {
        var r = SeededRandom(seed: 9)
        var ou = OrnsteinUhlenbeck(sigma: 3, tauSeconds: 2, rng: &r)
        var xs: [Double] = []
        for _ in 0..<200_000 { xs.append(ou.step(dt: 0.05, rng: &r)) }
        let mean = xs.reduce(0, +) / Double(xs.count)
        let sd = (xs.map { ($0 - mean) * ($0 - mean) }.reduce(0, +) / Double(xs.count)).squareRoot()
        XCTAssertEqual(sd, 3, accuracy: 0.3)
        XCTAssertEqual(mean, 0, accuracy: 0.5)
    }

    func testWrapAngle() {
        XCTAssertEqual(wrapAngle(3 * Double.pi), Double.pi, accuracy: 1e-12)
        XCTAssertEqual(wrapAngle(-Double.pi / 2 - 2 * Double.pi), -Double.pi / 2, accuracy: 1e-12)
    }
}
