// The sign-kind catalogue of a building: for each kind of sign, the physical size of its face (which range
// estimation needs: the apparent-height method's h0), its colours and whether it has two faces. Map format v1
// carries it as the optional top-level "signKinds" (Maps/schema/map-v1.schema.json, docs/map-format.md); a map
// without it gets one entry per kind its signs use, sized like those signs, and the default Exit sign.

/// One kind of sign and the size of its face.
public struct SignKindSpec: Codable, Hashable, Sendable {
    /// Sign class as signs and detections name it, e.g. `exit`.
    public var kind: String
    /// Height of the face, meters (> 0): the apparent-height method's h0.
    public var heightMeters: Double
    /// Width of the face, meters (> 0).
    public var widthMeters: Double
    /// Background colour of the face, e.g. "white"; nil = unknown.
    public var faceColor: String?
    /// Colour of the legend (lettering, pictogram), e.g. "red"; nil = unknown.
    public var legendColor: String?
    /// Whether signs of this kind have a face on both sides (hung across a corridor).
    public var doubleSided: Bool
    /// Farthest horizontal range at which the detector recognises this kind, meters; nil = the localizer's
    /// default (12 m, what the Exit-sign detectors reach). Small legends are recognised from closer: a
    /// room-number placard's 25 mm digits are about 20 px tall at 2 m on an iPhone's 1920 x 1440 frame, what
    /// text recognition needs, so such a kind states about 2.5 m.
    public var maxRangeMeters: Double?
    /// Largest angle between the face normal and the line of sight at which the kind is recognised, degrees;
    /// nil = the default of whoever asks: the localizer's looser 80 (LocalizerCore `max_view_angle_from_normal_rad`),
    /// the detector's `SignKindSpec.detectorMaxViewAngleDeg` where the detector is modelled. Text is read only fairly
    /// square on (about 50).
    public var maxViewAngleDeg: Double?
    /// Largest angle from a face's normal at which the sign detectors find a sign of a kind that states no
    /// `maxViewAngleDeg`, degrees: seen more obliquely, a face is foreshortened to a sliver (cos 75 degrees = 0.26
    /// of its width) that no detector finds. The simulator's detector model (`DetectorParameters`) and the pipeline's
    /// prediction of the kinds in view (`ExpectedSignKinds`) both start from it.
    public static let detectorMaxViewAngleDeg = 75.0
    /// Typical height of the face's bottom edge above the floor, meters; nil = not stated (Exit signs: the
    /// detector's own placement prior). The cascade of a kind that is not Exit-like searches the rows where a face
    /// at this height can appear (docs/sign-detection.md "More sign kinds"): ADA 703.4.1 puts tactile signs
    /// (placards, restroom, elevator and stairs pictograms) with their characters 1.22-1.52 m above the floor.
    public var mountingHeightMeters: Double?
    /// Whether the legend is text that identifies the sign (a room number): the detector reads it and the
    /// localizer matches the sighting to the one sign with that text.
    public var readsText: Bool

    /// Creates a catalogue entry.
    public init(kind: String, heightMeters: Double, widthMeters: Double, faceColor: String? = nil,
                legendColor: String? = nil, doubleSided: Bool = false, maxRangeMeters: Double? = nil,
                maxViewAngleDeg: Double? = nil, mountingHeightMeters: Double? = nil, readsText: Bool = false) {
        self.kind = kind; self.heightMeters = heightMeters; self.widthMeters = widthMeters
        self.faceColor = faceColor; self.legendColor = legendColor; self.doubleSided = doubleSided
        self.maxRangeMeters = maxRangeMeters; self.maxViewAngleDeg = maxViewAngleDeg
        self.mountingHeightMeters = mountingHeightMeters; self.readsText = readsText
    }

    /// Decodes an entry; `doubleSided` and `readsText` default to false, the recognition limits and the mounting
    /// height to nil.
    public init(from decoder: Decoder) throws {
        let c = try decoder.container(keyedBy: CodingKeys.self)
        self.init(kind: try c.decode(String.self, forKey: .kind), heightMeters: try c.decode(Double.self, forKey: .heightMeters),
                  widthMeters: try c.decode(Double.self, forKey: .widthMeters),
                  faceColor: try c.decodeIfPresent(String.self, forKey: .faceColor),
                  legendColor: try c.decodeIfPresent(String.self, forKey: .legendColor),
                  doubleSided: try c.decodeIfPresent(Bool.self, forKey: .doubleSided) ?? false,
                  maxRangeMeters: try c.decodeIfPresent(Double.self, forKey: .maxRangeMeters),
                  maxViewAngleDeg: try c.decodeIfPresent(Double.self, forKey: .maxViewAngleDeg),
                  mountingHeightMeters: try c.decodeIfPresent(Double.self, forKey: .mountingHeightMeters),
                  readsText: try c.decodeIfPresent(Bool.self, forKey: .readsText) ?? false)
    }

    /// The Exit sign of the project's buildings (the Smith-Kettlewell signs measured for the paper, and the
    /// bundled office): a face 0.30 m wide and 0.21 m high, red legend on white.
    public static let defaultExit = SignKindSpec(kind: "exit", heightMeters: 0.21, widthMeters: 0.30,
                                                 faceColor: "white", legendColor: "red")

    /// Tactile pictogram signs (ADA 703.6 pictograms with a 6 in = 0.15 m field; the plates are about 9 in =
    /// 0.23 m square), white on a blue (restroom) or dark plate, beside the door they name, bottom edge 1.35 m above
    /// the floor (ADA 703.4.1: tactile characters 1.22-1.52 m up). Recognised out to 6 m (a 0.23 m face is then
    /// 20 px tall on the cascade's VGA frame, about the smallest its 20 x 20 window finds) and 60 degrees off square.
    public static let restroomPictogram = tactilePictogram(kind: "restroom", faceColor: "blue")
    /// The elevator pictogram plate (see `restroomPictogram`), white on dark.
    public static let elevatorPictogram = tactilePictogram(kind: "elevator", faceColor: "dark")
    /// The stairs pictogram plate (see `restroomPictogram`), white on dark.
    public static let stairsPictogram = tactilePictogram(kind: "stairs", faceColor: "dark")

    /// A 0.23 m square tactile pictogram plate of `kind`, white legend on `faceColor`, mounted and recognised as
    /// `restroomPictogram` says.
    static func tactilePictogram(kind: String, faceColor: String) -> SignKindSpec {
        SignKindSpec(kind: kind, heightMeters: 0.23, widthMeters: 0.23, faceColor: faceColor, legendColor: "white",
                     maxRangeMeters: 6, maxViewAngleDeg: 60, mountingHeightMeters: 1.35)
    }
    /// A room-number placard: a 0.15 m square dark plate with 25 mm light digits, beside the door on the latch side,
    /// bottom edge 1.35 m above the floor; its legend (the room number, `Sign.text`) is read by text recognition
    /// from at most 2.5 m and 50 degrees off square (25 mm digits are about 20 px tall at 2 m on the phone's
    /// 1920 x 1440 frame).
    public static let roomPlacard = SignKindSpec(kind: "placard", heightMeters: 0.15, widthMeters: 0.15, faceColor: "dark",
                                                 legendColor: "white", maxRangeMeters: 2.5, maxViewAngleDeg: 50,
                                                 mountingHeightMeters: 1.35, readsText: true)
}

/// The sign kinds of a building, one entry per kind.
public struct SignCatalogue: Hashable, Sendable {
    /// Entries, kinds unique.
    public var kinds: [SignKindSpec]

    /// Wraps entries (not checked; see `MapValidator` for a map's "signKinds" and `Building.signCatalogue`).
    public init(kinds: [SignKindSpec]) { self.kinds = kinds }

    /// Only the default Exit sign (`SignKindSpec.defaultExit`).
    public static let defaultCatalogue = SignCatalogue(kinds: [.defaultExit])

    /// The entry of `kind`, or nil.
    public func spec(kind: String) -> SignKindSpec? { kinds.first { $0.kind == kind } }

    /// Face height of `kind`, meters, or nil when the catalogue does not know the kind.
    public func heightMeters(kind: String) -> Double? { spec(kind: kind)?.heightMeters }
}

extension Building {
    /// The building's sign-kind catalogue: its "signKinds" when the map has them; otherwise one entry per kind
    /// its signs use, sized like the most common size among that kind's signs (ties: the first sign's), plus
    /// `SignKindSpec.defaultExit` when no sign is an Exit sign.
    public var signCatalogue: SignCatalogue {
        if let explicit = signKinds { return SignCatalogue(kinds: explicit) }
        var order: [String] = []
        var sizes: [String: [(width: Double, height: Double, doubleSided: Bool)]] = [:]
        for sign in floors.flatMap(\.signs) {
            if sizes[sign.kind] == nil { order.append(sign.kind) }
            sizes[sign.kind, default: []].append((sign.widthMeters, sign.heightMeters, sign.doubleSided))
        }
        var kinds = order.map { kind -> SignKindSpec in
            let all = sizes[kind]!
            var best = all[0], bestCount = 0
            for candidate in all {
                let count = all.filter { $0.width == candidate.width && $0.height == candidate.height }.count
                if count > bestCount { best = candidate; bestCount = count }
            }
            let colours = kind == SignKindSpec.defaultExit.kind ? SignKindSpec.defaultExit : nil
            return SignKindSpec(kind: kind, heightMeters: best.height, widthMeters: best.width,
                                faceColor: colours?.faceColor, legendColor: colours?.legendColor,
                                doubleSided: all.allSatisfy(\.doubleSided))
        }
        if sizes[SignKindSpec.defaultExit.kind] == nil { kinds.append(.defaultExit) }
        return SignCatalogue(kinds: kinds)
    }
}
