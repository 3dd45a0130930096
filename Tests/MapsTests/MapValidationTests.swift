import Foundation
import XCTest
@testable import Maps

/// One test per kind of damage: each asserts the one error names the file, the JSON path and the reason.
final class MapValidationTests: XCTestCase {
    // MARK: JSON and types

    func testNotJSON() {
        assertRejects("this is not a map", path: "$", reason: "not valid JSON")
    }

    func testTruncatedJSON() throws {
        let t = try MapFixtures.text()
        assertRejects(String(t.prefix(t.count / 2)), path: "$", reason: "truncated JSON")
    }

    func testEmptyFile() {
        assertRejects("", path: "$", reason: "the file is empty")
    }

    func testWrongFormatVersion() throws {
        assertRejects(try MapFixtures.text(replacing: "\"formatVersion\" : 1", with: "\"formatVersion\" : 2"),
                      path: "$.formatVersion", reason: "unsupported formatVersion 2")
    }

    func testFormatVersionNotAnInteger() throws {
        assertRejects(try MapFixtures.text(replacing: "\"formatVersion\" : 1", with: "\"formatVersion\" : \"1\""),
                      path: "$.formatVersion", reason: "formatVersion must be the integer 1")
    }

    func testMissingRequiredField() throws {
        assertRejects(try MapFixtures.text(replacing: "\"name\" : \"Upper floor\",", with: ""),
                      path: "$.floors[1].name", reason: "missing required field 'name'")
    }

    func testWrongType() throws {
        assertRejects(try MapFixtures.text(replacing: "\"elevationMeters\" : 3.5", with: "\"elevationMeters\" : \"high\""),
                      path: "$.floors[1].elevationMeters", reason: "expected a number, got a string")
    }

    func testPointWithThreeNumbers() throws {
        assertRejects(try MapFixtures.text(replacing: "\"position\" : [2.5, 1.5]", with: "\"position\" : [2.5, 1.5, 0]"),
                      path: "$.floors[1].pointsOfInterest[0].position", reason: "two numbers")
    }

    func testNaNString() throws {
        assertRejects(try MapFixtures.text(replacing: "\"facing\" : [0, -1]", with: "\"facing\" : [\"NaN\", -1]"),
                      path: "$.floors[1].signs[0].facing[0]", reason: "NaN and infinity are not allowed")
    }

    func testInfiniteNumber() throws {
        assertRejects(try MapFixtures.text(replacing: "\"elevationMeters\" : 3.5", with: "\"elevationMeters\" : 1e999"),
                      path: "$.floors[1].elevationMeters", reason: "number out of range")
    }

    func testOutOfRangeCoordinate() throws {
        assertRejects(try MapFixtures.text(replacing: "\"position\" : [2.5, 1.5]", with: "\"position\" : [2.5e9, 1.5]"),
                      path: "$.floors[1].pointsOfInterest[0].position[0]", reason: "out of range")
    }

    func testOutOfRangeMountingHeight() throws {
        assertRejects(try MapFixtures.text(replacing: "\"mountingHeightMeters\" : 2.3", with: "\"mountingHeightMeters\" : -2.3"),
                      path: "$.floors[0].signs[0].mountingHeightMeters", reason: "out of range")
    }

    func testUnknownField() throws {
        assertRejects(try MapFixtures.text(replacing: "\"widthMeters\" : 0.31", with: "\"widthMeters\" : 0.31, \"colour\" : \"red\""),
                      path: "$.floors[1].signs[0].colour", reason: "unknown field 'colour'")
    }

    func testDuplicateJSONKey() throws {
        assertRejects(try MapFixtures.text(replacing: "\"widthMeters\" : 0.31", with: "\"widthMeters\" : 0.31, \"widthMeters\" : 0.5"),
                      path: "$", reason: "duplicate member name \"widthMeters\"")
    }

    func testUnknownNodeKind() throws {
        // The first control node in the file is nodes[1] ("c1").
        assertRejects(try MapFixtures.text(replacingFirst: "\"kind\" : \"control\"", with: "\"kind\" : \"junction\""),
                      path: "$.graph.nodes[1].kind", reason: "unknown node kind \"junction\"")
    }

    // MARK: structure

    func testEmptyBuilding() throws {
        try assertRejects(damage: { $0.floors = [] }, path: "$.floors", reason: "no floors (empty building)")
    }

    func testFloorWithNoWalls() throws {
        try assertRejects(damage: { $0.floors[1].walls = [] }, path: "$.floors[1].walls", reason: "has no walls")
    }

    func testDegenerateWall() throws {
        try assertRejects(damage: { $0.floors[0].walls[2] = Wall(from: Point2(3, 4), to: Point2(3, 4)) },
                          path: "$.floors[0].walls[2]", reason: "degenerate wall")
    }

    func testDuplicateFloorIds() throws {
        try assertRejects(damage: { $0.floors[1].id = "1" }, path: "$.floors[1].id", reason: "duplicate floor id \"1\"")
    }

    func testDuplicateNodeIds() throws {
        try assertRejects(damage: { $0.graph.nodes[4].id = "c1" }, path: "$.graph.nodes[4].id", reason: "duplicate node id \"c1\"")
    }

    func testDuplicatePointOfInterestIds() throws {
        try assertRejects(damage: { $0.floors[1].pointsOfInterest[0].id = "poi-a" },
                          path: "$.floors[1].pointsOfInterest[0].id", reason: "duplicate point-of-interest id \"poi-a\"")
    }

    func testDuplicateSignIds() throws {
        try assertRejects(damage: { b in
            var s = b.floors[0].signs[0]
            s.position = Point2(0, 3)
            b.floors[0].signs.append(s)
        }, path: "$.floors[0].signs[1].id", reason: "duplicate sign id \"s1\"")
    }

    func testEmptyIdentifier() throws {
        try assertRejects(damage: { $0.graph.nodes[1].id = " " }, path: "$.graph.nodes[1].id", reason: "must not be empty")
    }

    // MARK: signs

    func testSignNotNearAWall() throws {
        try assertRejects(damage: { $0.floors[1].signs[0].position = Point2(5, 3.6) },
                          path: "$.floors[1].signs[0].position", reason: "is not on a wall: the nearest wall is 0.4 m away")
    }

    func testProjectingSignFarFromEveryWall() throws {
        try assertRejects(damage: { b in
            b.floors[1].signs[0].position = Point2(5, 2)
            b.floors[1].signs[0].placement = .projecting
        }, path: "$.floors[1].signs[0].position", reason: "projecting sign \"s2\" is not near a wall")
    }

    func testSignFacingNotUnitLength() throws {
        try assertRejects(damage: { $0.floors[1].signs[0].facing = Point2(0, -0.5) },
                          path: "$.floors[1].signs[0].facing", reason: "facing must be a unit vector, its length is 0.5")
    }

    func testSignFacingZero() throws {
        try assertRejects(damage: { $0.floors[0].signs[0].facing = Point2(0, 0) },
                          path: "$.floors[0].signs[0].facing", reason: "facing is the zero vector")
    }

    func testSignNonPositiveSize() throws {
        try assertRejects(damage: { $0.floors[0].signs[0].heightMeters = 0 },
                          path: "$.floors[0].signs[0].heightMeters", reason: "sign size must be positive")
        try assertRejects(damage: { $0.floors[1].signs[0].widthMeters = -0.3 },
                          path: "$.floors[1].signs[0].widthMeters", reason: "sign size must be positive")
    }

    func testUnknownSignPlacement() throws {
        assertRejects(try MapFixtures.text(replacing: "\"widthMeters\" : 0.31", with: "\"widthMeters\" : 0.31, \"placement\" : \"floating\"")
                        .replacingOccurrences(of: "\"placement\" : \"wall\",\n          \"position\" : [5, 4]", with: "\"position\" : [5, 4]"),
                      path: "$.floors[1].signs[0].placement", reason: "unknown sign placement \"floating\"")
    }

    // MARK: graph

    func testNodeOnUnknownFloor() throws {
        try assertRejects(damage: { $0.graph.nodes[4].floorId = "7" }, path: "$.graph.nodes[4].floorId", reason: "unknown floor \"7\"")
    }

    func testDanglingEdge() throws {
        try assertRejects(damage: { $0.graph.edges[3].to = "nowhere" }, path: "$.graph.edges[3].to",
                          reason: "unknown node \"nowhere\" (dangling edge)")
    }

    func testSelfLoopEdge() throws {
        try assertRejects(damage: { $0.graph.edges.append(GraphEdge(from: "c2", to: "c2")) }, path: "$.graph.edges[5]",
                          reason: "self-loop")
    }

    func testDuplicateEdge() throws {
        try assertRejects(damage: { $0.graph.edges.append(GraphEdge(from: "b", to: "c2")) }, path: "$.graph.edges[5]",
                          reason: "duplicate edge between \"b\" and \"c2\"")
    }

    func testPointOfInterestNodeWithUnknownPointOfInterest() throws {
        try assertRejects(damage: { $0.graph.nodes[5].pointOfInterestId = "poi-zzz" }, path: "$.graph.nodes[5].pointOfInterestId",
                          reason: "unknown point of interest \"poi-zzz\"")
    }

    func testPointOfInterestNodeWithoutPointOfInterestId() throws {
        try assertRejects(damage: { $0.graph.nodes[5].pointOfInterestId = nil }, path: "$.graph.nodes[5].pointOfInterestId",
                          reason: "must name its point of interest")
    }

    func testPointOfInterestWithoutGraphNode() throws {
        try assertRejects(damage: { b in
            b.floors[0].pointsOfInterest.append(PointOfInterest(id: "poi-c", name: "Room C", category: "room", position: Point2(4, 1), behindDoor: false))
        }, path: "$.floors[0].pointsOfInterest[1]", reason: "point of interest \"poi-c\" has no graph node")
    }

    func testPointOfInterestNodeOnOtherFloor() throws {
        try assertRejects(damage: { $0.graph.nodes[5].pointOfInterestId = "poi-a" }, path: "$.graph.nodes[5].floorId",
                          reason: "its point of interest \"poi-a\" is on floor \"1\"")
    }

    func testVerticalLinkWithoutCounterpart() throws {
        try assertRejects(damage: { b in
            b.graph.nodes.append(GraphNode(id: "st1", kind: .verticalLink, floorId: "1", position: Point2(9, 3), verticalLink: .stairs))
            b.graph.edges.append(GraphEdge(from: "e1", to: "st1"))
        }, path: "$.graph.nodes[6]", reason: "verticalLink node \"st1\" has no counterpart")
    }

    func testVerticalLinkWithoutKind() throws {
        try assertRejects(damage: { $0.graph.nodes[2].verticalLink = nil }, path: "$.graph.nodes[2].verticalLink",
                          reason: "must say \"elevator\" or \"stairs\"")
    }

    func testVerticalEdgeBetweenNonLinkNodes() throws {
        try assertRejects(damage: { $0.graph.edges.append(GraphEdge(from: "c1", to: "c2")) }, path: "$.graph.edges[5]",
                          reason: "must join two verticalLink nodes")
    }

    func testVerticalEdgeBetweenElevatorAndStairs() throws {
        try assertRejects(damage: { $0.graph.nodes[3].verticalLink = .stairs }, path: "$.graph.edges[2]",
                          reason: "vertical edge joins elevator node \"e1\" to stairs node \"e2\"")
    }

    func testDisconnectedGraph() throws {
        try assertRejects(damage: { $0.graph.edges.remove(at: 4) }, path: "$.graph.nodes[5]",
                          reason: "the navigation graph is disconnected: node \"b\" cannot be reached")
    }

    func testGraphWithoutNodes() throws {
        try assertRejects(damage: { b in
            b.graph = NavigationGraph(nodes: [], edges: [])
            b.floors[0].pointsOfInterest = []; b.floors[1].pointsOfInterest = []
        }, path: "$.graph.nodes", reason: "no nodes")
    }

    func testNonPositiveDoorWidth() throws {
        try assertRejects(damage: { $0.floors[0].doors[0].widthMeters = 0 }, path: "$.floors[0].doors[0].widthMeters",
                          reason: "door width must be a positive number")
    }

    // MARK: validation of buildings made in code

    func testValidatorNamesPathForInMemoryBuilding() {
        var b = MapFixtures.building()
        b.floors[0].elevationMeters = .nan
        XCTAssertThrowsError(try MapValidator.validate(b)) { e in
            let m = e as! MapError
            XCTAssertEqual(m.file, "<memory>")
            XCTAssertEqual(m.jsonPath, "$.floors[0].elevationMeters")
            XCTAssertTrue(m.reason.contains("finite"))
        }
        XCTAssertThrowsError(try MapWriter.encode(b), "the writer refuses an invalid building")
    }

    func testFixtureIsValid() throws {
        XCTAssertNoThrow(try MapValidator.validate(MapFixtures.building()))
    }
}
