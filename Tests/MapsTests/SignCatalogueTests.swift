import Foundation
import XCTest
@testable import Maps

/// The sign-kind catalogue of map format v1 ("signKinds"): loading, writing, defaults, and clear errors for an
/// empty or contradictory catalogue.
final class SignCatalogueTests: XCTestCase {
    private let restroom = SignKindSpec(kind: "restroom", heightMeters: 0.2, widthMeters: 0.15, faceColor: "blue",
                                        legendColor: "white", doubleSided: true)

    func testWithoutSignKindsTheCatalogueComesFromTheSignsAndTheDefaultExit() throws {
        let b = MapFixtures.building()
        XCTAssertNil(b.signKinds)
        // Two Exit signs of different sizes, one each: the first sign's size wins the tie; not every one is
        // double-sided.
        let exit = try XCTUnwrap(b.signCatalogue.spec(kind: "exit"))
        XCTAssertEqual(exit.heightMeters, 0.21)
        XCTAssertEqual(exit.widthMeters, 0.3)
        XCTAssertFalse(exit.doubleSided)
        XCTAssertEqual(b.signCatalogue.kinds.count, 1)
        // A building without signs still ranges Exit signs with the default size.
        var empty = b
        for i in empty.floors.indices { empty.floors[i].signs = [] }
        XCTAssertEqual(empty.signCatalogue, SignCatalogue.defaultCatalogue)
        XCTAssertEqual(SignCatalogue.defaultCatalogue.heightMeters(kind: "exit"), 0.21)
        XCTAssertNil(SignCatalogue.defaultCatalogue.heightMeters(kind: "restroom"))
    }

    func testTheMostCommonSizeOfAKindWins() {
        var b = MapFixtures.building()
        var extra = b.floors[1].signs[0]
        extra.id = "s3"
        b.floors[1].signs.append(extra)  // now 0.31 x 0.22 twice against 0.30 x 0.21 once
        XCTAssertEqual(b.signCatalogue.heightMeters(kind: "exit"), 0.22)
    }

    func testSignKindsLoadAndRoundTripThroughTheWriter() throws {
        var b = MapFixtures.building()
        b.floors[1].signs[0].widthMeters = 0.3
        b.floors[1].signs[0].heightMeters = 0.21
        b.signKinds = [.defaultExit, restroom]
        let text = try MapFixtures.text(of: b)
        XCTAssertTrue(text.contains("\"signKinds\""))
        let loaded = try MapLoader.load(data: Data(text.utf8), fileName: MapFixtures.fileName)
        XCTAssertEqual(loaded.signKinds, [.defaultExit, restroom])
        XCTAssertEqual(loaded.signCatalogue.spec(kind: "restroom"), restroom)
        XCTAssertEqual(try MapLoader.load(data: try MapWriter.encode(loaded), fileName: "again.json"), loaded)
        // A map without the section writes none.
        XCTAssertFalse(try MapFixtures.text().contains("signKinds"))
    }

    func testDoubleSidedDefaultsToFalseAndUnknownFieldsAreRejected() throws {
        let text = try MapFixtures.text(replacingFirst: "\"floors\"",
                                        with: "\"signKinds\" : [{\"kind\": \"exit\", \"heightMeters\": 0.21, \"widthMeters\": 0.3}], \"floors\"")
        var withSizes = text.replacingOccurrences(of: "0.31", with: "0.3").replacingOccurrences(of: "0.22", with: "0.21")
        let loaded = try MapLoader.load(data: Data(withSizes.utf8), fileName: MapFixtures.fileName)
        XCTAssertEqual(loaded.signKinds?.first?.doubleSided, false)
        withSizes = withSizes.replacingOccurrences(of: "\"widthMeters\": 0.3}", with: "\"widthMeters\": 0.3, \"size\": 1}")
        assertRejects(withSizes, path: "$.signKinds[0].size", reason: "unknown field 'size'")
    }

    func testAnEmptyCatalogueIsAClearError() throws {
        try assertRejects(damage: { $0.signKinds = [] }, path: "$.signKinds", reason: "signKinds is empty")
    }

    func testAContradictoryCatalogueIsAClearError() throws {
        // The same kind twice.
        try assertRejects(damage: { $0.signKinds = [.defaultExit, SignKindSpec(kind: "exit", heightMeters: 0.25, widthMeters: 0.3)] },
                          path: "$.signKinds[1].kind", reason: "sign kind \"exit\" is listed twice")
        // A sign whose size contradicts its kind's.
        try assertRejects(damage: { $0.signKinds = [.defaultExit] }, path: "$.floors[1].signs[0]",
                          reason: "contradictory sizes")
        // A sign of a kind the catalogue lacks.
        try assertRejects(damage: { b in
            b.signKinds = [SignKindSpec(kind: "exit", heightMeters: 0.21, widthMeters: 0.3)]
            b.floors[1].signs[0].kind = "stairs"
        }, path: "$.floors[1].signs[0].kind", reason: "sign kind \"stairs\" is not in $.signKinds")
    }

    func testCatalogueSizesMustBePositiveFiniteAndPlausible() throws {
        for bad in [0, -0.2, 6] {  // (NaN cannot be written as JSON; the reader rejects it as a number)
            try assertRejects(damage: { $0.signKinds = [SignKindSpec(kind: "exit", heightMeters: bad, widthMeters: 0.3)] },
                              path: "$.signKinds[0].heightMeters", reason: "sign face size must be in (0, 5] m")
        }
        try assertRejects(damage: { $0.signKinds = [SignKindSpec(kind: "", heightMeters: 0.21, widthMeters: 0.3)] },
                          path: "$.signKinds[0].kind", reason: "sign kind must not be empty")
    }

    /// Identifying legends (`Sign.text`) and a kind's own recognition limits: they round-trip, and a bad one
    /// is refused naming the field.
    func testSignTextAndRecognitionLimits() throws {
        var b = MapFixtures.building()
        b.floors[1].signs[0].text = "402"
        b.signKinds = nil
        let loaded = try MapLoader.load(data: try MapWriter.encode(b), fileName: "text.json")
        XCTAssertEqual(loaded.floors[1].signs[0].text, "402")
        XCTAssertNil(loaded.floors[0].signs.first?.text)
        XCTAssertFalse(try MapFixtures.text().contains("\"text\""), "absent text is not written")

        let placard = SignKindSpec(kind: "placard", heightMeters: 0.15, widthMeters: 0.15, maxRangeMeters: 2.5, maxViewAngleDeg: 50)
        var withKinds = MapFixtures.building()
        withKinds.floors[1].signs[0].widthMeters = 0.3
        withKinds.floors[1].signs[0].heightMeters = 0.21
        withKinds.signKinds = [.defaultExit, placard]
        let again = try MapLoader.load(data: try MapWriter.encode(withKinds), fileName: "kinds.json")
        XCTAssertEqual(again.signCatalogue.spec(kind: "placard")?.maxRangeMeters, 2.5)
        XCTAssertEqual(again.signCatalogue.spec(kind: "placard")?.maxViewAngleDeg, 50)
        XCTAssertNil(again.signCatalogue.spec(kind: "exit")?.maxRangeMeters)

        try assertRejects(damage: { $0.floors[1].signs[0].text = "" }, path: "$.floors[1].signs[0].text",
                          reason: "sign text must be 1 to 40 characters")
        try assertRejects(damage: { $0.floors[1].signs[0].text = " 402" }, path: "$.floors[1].signs[0].text",
                          reason: "without surrounding spaces")
        try assertRejects(damage: { b in
            var twin = b.floors[1].signs[0]
            twin.id = "twin"
            twin.text = "402"
            b.floors[1].signs[0].text = "402"
            b.floors[1].signs.append(twin)
        }, path: "$.floors[1].signs[1].text", reason: "is also on $.floors[1].signs[0]")
        func withPlacardKind(_ change: @escaping (inout SignKindSpec) -> Void) -> (inout Building) -> Void {
            { b in
                b.floors[1].signs[0].widthMeters = 0.3
                b.floors[1].signs[0].heightMeters = 0.21
                var bad = placard
                change(&bad)
                b.signKinds = [.defaultExit, bad]
            }
        }
        try assertRejects(damage: withPlacardKind { $0.maxRangeMeters = 0 }, path: "$.signKinds[1].maxRangeMeters",
                          reason: "recognition range (meters)")
        try assertRejects(damage: withPlacardKind { $0.maxViewAngleDeg = 120 }, path: "$.signKinds[1].maxViewAngleDeg",
                          reason: "recognition view angle (degrees)")
        try assertRejects(damage: withPlacardKind { $0.mountingHeightMeters = -1 }, path: "$.signKinds[1].mountingHeightMeters",
                          reason: "mounting height")
    }

    func testMountingHeightAndTextReadingRoundTripAndDefaultToAbsent() throws {
        var b = MapFixtures.building()
        b.floors[1].signs[0].widthMeters = 0.3
        b.floors[1].signs[0].heightMeters = 0.21
        let placard = SignKindSpec(kind: "placard", heightMeters: 0.15, widthMeters: 0.15, faceColor: "dark", legendColor: "white",
                                   maxRangeMeters: 2.5, maxViewAngleDeg: 50, mountingHeightMeters: 1.35, readsText: true)
        b.signKinds = [.defaultExit, placard]
        let loaded = try MapLoader.load(data: try MapWriter.encode(b), fileName: "kinds.json")
        XCTAssertEqual(loaded.signCatalogue.spec(kind: "placard"), placard)
        XCTAssertEqual(loaded.signCatalogue.spec(kind: "exit")?.readsText, false)
        XCTAssertNil(loaded.signCatalogue.spec(kind: "exit")?.mountingHeightMeters)
    }
}
