import Foundation
import Maps

/// Which detector runs.
public enum DetectorKind: String, Sendable, CaseIterable {
    /// One AdaBoost cascade per sign kind; rough boxes (fast).
    case cascade
    /// U-Net segmentation, coarse pass + zoomed pass per candidate; masks (accurate heights).
    case unet
}

/// A cascade model file and the sign kind it detects.
public struct CascadeModel: Sendable, Equatable {
    /// Kind name reported in detections ("exit", "restroom"...).
    public var kind: String
    /// Path of an OpenCV cascade XML file.
    public var path: String

    public init(kind: String, path: String) {
        self.kind = kind
        self.path = path
    }
}

/// Everything needed to create a SignDetector. Zero numeric values mean "the C side's default" (given in
/// each comment), so a configuration written today keeps working when defaults are tuned.
public struct DetectorConfiguration: Sendable, Equatable {
    /// Detector to run.
    public var kind: DetectorKind
    /// Cascades, one per sign kind (cascade detector).
    public var cascades: [CascadeModel]
    /// U-Net ONNX model path (U-Net detector).
    public var unetPath: String?
    /// U-Net class names, index 0 = background; empty = read classes.json next to the model.
    public var classNames: [String]
    /// Sign kinds and their face sizes (from the map: `Building.signCatalogue`), which `SignDetector.sense`
    /// ranges with; detections of other kinds are left out there. Empty: `detect` works, `sense` throws
    /// `SignDetectorError.invalidCatalogue`.
    public var catalogue: SignCatalogue = SignCatalogue(kinds: [])
    /// Detections scoring below this are dropped (cascade: neighbour count; U-Net: mean probability).
    public var minScore: Double
    /// Cascade scale step (0 = 1.2), minimum neighbours (0 = 3), smallest window (0 = the cascade's training
    /// window; the reference app used 36 x 24), largest window as a multiple of the smallest (0 = unlimited).
    public var cascadeScaleFactor: Double = 0
    public var cascadeMinNeighbors: Int = 0
    public var cascadeMinWindowWidth: Int = 0
    public var cascadeMinWindowHeight: Int = 0
    public var cascadeMaxWindowFactor: Double = 0
    /// If set, the cascade searches only unrolled rows whose ray elevation is at least this (radians; default
    /// -0.15): signs above eye level never appear far below the horizon, where floors and doors give false
    /// alarms. nil = the whole frame (kinds mounted low).
    public var cascadeMinElevationRad: Double? = -0.15
    /// Placement prior: height of a sign's centre above the camera, metres (default 0.3...2.0: Exit signs'
    /// bottom edges 2.03 to about 2.6 m above the floor, the phone 1.0 to 1.7 m). At each scale the cascade
    /// searches only the rows where a sign of that window size at such a height can appear (about 3 x fewer
    /// windows on the rendered test set). nil = every row (kinds whose height is not known).
    public var cascadeSignAboveCameraMeters: ClosedRange<Double>? = 0.3...2.0
    /// Colour gate, crowded frames: when the gate's regions cover more than 15 % of the searched frame, its
    /// contrast threshold is multiplied by this once (0 = the C default 2.5; 1 = off; otherwise > 1).
    public var cascadeGateCrowdedContrastFactor: Double = 0
    /// Colour gate: smallest margin around a colour blob's search region, pixels of the frame (0 = the C default
    /// 16; the earlier setting was 24).
    public var cascadeGateMinMarginPixels: Int = 0
    /// Colour gate, large colour components (cut into tiles): the smallest window searched in a tile's region as a
    /// fraction of the whole component's width (0 = the C default 0.4; nil = off, every window size: also finds a
    /// small sign merged into a large coloured stripe or poster edge, at about 1.2 x the time on the rendered test
    /// set). Otherwise in (0, 1].
    public var cascadeGateComponentWindowFraction: Double? = 0
    /// U-Net mask threshold (0 = 0.5), zoom factor (0 = 3.5), smallest crop in original pixels (0 = 64),
    /// most candidates zoomed per frame (0 = 8).
    public var unetMaskThreshold: Double = 0
    public var unetZoomFactor: Double = 0
    public var unetMinCropPx: Int = 0
    public var unetMaxCandidates: Int = 0
    /// U-Net coarse pass: rows whose ray elevation is below this are skipped (radians; 0 = the C default
    /// -0.10: Exit signs hang above eye level). nil = the whole frame (kinds mounted low).
    public var unetCoarseMinElevationRad: Double? = 0
    /// Slices: 0 = every column of the middle band, N = N columns; band fraction (0 = 0.6).
    public var sliceCount: Int = 0
    public var sliceBandFraction: Double = 0
    /// Rolls within this of a multiple of pi/2 are snapped to it (exact, faster); 0 = never. Radians.
    public var rollSnapToleranceRad: Double = 0

    /// The first cascade's path (the common one-kind case); setting it replaces the first cascade.
    public var cascadePath: String? {
        get { cascades.first?.path }
        set {
            if let path = newValue {
                if cascades.isEmpty { cascades = [CascadeModel(kind: "exit", path: path)] } else { cascades[0].path = path }
            } else if !cascades.isEmpty {
                cascades.removeFirst()
            }
        }
    }

    /// A configuration with the given models; `cascadePath` becomes one cascade of kind `cascadeKind`.
    public init(kind: DetectorKind, cascadePath: String? = nil, cascadeKind: String = "exit",
                unetPath: String? = nil, classNames: [String] = [], minScore: Double = 0,
                catalogue: SignCatalogue = SignCatalogue(kinds: [])) {
        self.kind = kind
        self.catalogue = catalogue
        self.cascades = cascadePath.map { [CascadeModel(kind: cascadeKind, path: $0)] } ?? []
        self.unetPath = unetPath
        self.classNames = classNames
        self.minScore = minScore
    }

    /// File names inside a models directory (SignDetector/models).
    public static let cascadeFileName = "exit_sign_cascade.xml"
    public static let unetFileName = "sign_unet.onnx"
    public static let classListFileName = "classes.json"

    /// Cascade file of a sign kind other than the Exit sign: `<kind>_cascade.xml` (restroom, elevator, stairs,
    /// placard: SignDetector/training/train_cascade.py --kind).
    public static func cascadeFileName(kind: String) -> String {
        kind == "exit" ? cascadeFileName : kind + "_cascade.xml"
    }

    /// How high above the phone a kind's face centre can be, meters, for the cascade's placement prior: from the
    /// kind's `mountingHeightMeters` (bottom edge above the floor) for a phone held 1.0 (a wheelchair user) to
    /// 1.7 m up, 0.1 m of margin each way. nil = not stated: the detector's Exit-sign placement.
    public static func placementBand(_ kind: SignKindSpec) -> ClosedRange<Double>? {
        guard let mount = kind.mountingHeightMeters, mount.isFinite else { return nil }
        let centre = mount + 0.5 * kind.heightMeters
        return (centre - 1.7 - 0.1)...(centre - 1.0 + 0.1)
    }

    /// The extra cascades of `catalogue`'s kinds found in `directory` (`cascadeFileName(kind:)`), leaving out the
    /// Exit sign and the kinds in `except` (a U-Net's classes), in catalogue order.
    static func extraCascades(directory: String, catalogue: SignCatalogue, except: Set<String>) -> [CascadeModel] {
        catalogue.kinds.compactMap { k in
            guard k.kind != "exit", !except.contains(k.kind) else { return nil }
            let path = directory + "/" + cascadeFileName(kind: k.kind)
            return FileManager.default.isReadableFile(atPath: path) ? CascadeModel(kind: k.kind, path: path) : nil
        }
    }

    /// The product's models: `<modelsDirectory>/exit_sign_cascade.xml`, or `sign_unet.onnx` with the class
    /// names of `classes.json` (when readable); either way plus `<kind>_cascade.xml` for each other kind of the
    /// catalogue whose file is there (beside the U-Net: the kinds it has no class for). Without `modelsDirectory`, the first of these that exists is
    /// used: $WAYFINDER_MODELS_DIR, the app bundle's `models` folder, `SignDetector/models` under the package
    /// root (found from this source file's location, then from the current directory upwards). Never
    /// throws: a missing file is reported by SignDetector.init, naming the path. `catalogue`: the map's sign
    /// kinds (`Building.signCatalogue`); the default is the default Exit sign alone.
    public static func bundled(kind: DetectorKind, modelsDirectory: String? = nil,
                               catalogue: SignCatalogue = .defaultCatalogue) -> DetectorConfiguration {
        let directory = modelsDirectory ?? locateModelsDirectory() ?? "SignDetector/models"
        switch kind {
        case .cascade:
            var c = DetectorConfiguration(kind: .cascade, cascadePath: directory + "/" + cascadeFileName, catalogue: catalogue)
            c.cascades += extraCascades(directory: directory, catalogue: catalogue, except: [])
            return c
        case .unet:
            let classes = readClassNames(path: directory + "/" + classListFileName) ?? []
            var c = DetectorConfiguration(kind: .unet, unetPath: directory + "/" + unetFileName, classNames: classes,
                                          catalogue: catalogue)
            c.cascades = extraCascades(directory: directory, catalogue: catalogue,
                                       except: Set(classes.isEmpty ? ["exit"] : classes))
            return c
        }
    }

    /// Class names of a classes.json ({"classes": ["background", "exit", ...]}), or nil if unreadable.
    public static func readClassNames(path: String) -> [String]? {
        struct ClassList: Decodable { var classes: [String] }
        guard let data = FileManager.default.contents(atPath: path),
              let list = try? JSONDecoder().decode(ClassList.self, from: data), list.classes.count >= 2
        else { return nil }
        return list.classes
    }

    static func locateModelsDirectory() -> String? {
        let fm = FileManager.default
        var isDirectory: ObjCBool = false
        func exists(_ path: String) -> Bool { fm.fileExists(atPath: path, isDirectory: &isDirectory) && isDirectory.boolValue }
        if let env = ProcessInfo.processInfo.environment["WAYFINDER_MODELS_DIR"], exists(env) { return env }
        if let resources = Bundle.main.resourcePath, exists(resources + "/models") { return resources + "/models" }
        // This file is <root>/SignDetector/Swift/DetectorConfiguration.swift.
        let fromSource = URL(fileURLWithPath: #filePath).deletingLastPathComponent().deletingLastPathComponent()
            .appendingPathComponent("models").path
        if exists(fromSource) { return fromSource }
        var dir = URL(fileURLWithPath: fm.currentDirectoryPath)
        for _ in 0..<8 {
            let candidate = dir.appendingPathComponent("SignDetector/models").path
            if exists(candidate) { return candidate }
            dir.deleteLastPathComponent()
        }
        return nil
    }
}
