// swift-tools-version:6.0
// Wayfinder: accessible indoor wayfinding. One package builds every Linux-testable module; the iOS app
// (project.yml) compiles the same sources plus App/iOS.
import PackageDescription

/// Compiler flags for the C++ cores: optimised even in debug builds (the particle filter and detectors
/// are too slow unoptimised for tests), system Eigen and OpenCV headers from Debian's packages.
let cxxCoreFlags: [CXXSetting] = [
    .unsafeFlags(["-O2", "-I/usr/include/eigen3", "-I/usr/include/opencv4"]),
]
let openCVLibraries: [LinkerSetting] = [
    "opencv_core", "opencv_imgproc", "opencv_imgcodecs", "opencv_objdetect", "opencv_dnn", "opencv_calib3d",
].map { .linkedLibrary($0) }

let package = Package(
    name: "Wayfinder",
    products: [
        .executable(name: "wayfinder", targets: ["WayfinderCLI"]),
        .executable(name: "wayfinder-fuzz", targets: ["WayfinderFuzz"]),
    ],
    targets: [
        // The status vocabulary shared by the C ABIs of LocalizerCore and SignDetector (wf_status.h).
        .target(name: "WayfinderStatus", path: "WayfinderStatus", sources: ["src"], publicHeadersPath: "include"),
        // C++17 particle filter behind the C ABI in LocalizerCore/include (the filter alone).
        .target(
            name: "LocalizerCore",
            dependencies: ["WayfinderStatus"],
            path: "LocalizerCore",
            sources: ["src"],
            publicHeadersPath: "include",
            cxxSettings: cxxCoreFlags + [.headerSearchPath("src")]
        ),
        // Swift wrapper over LocalizerCore (no C type in its public API).
        .target(name: "Localizer", dependencies: ["LocalizerCore", "Maps"], path: "LocalizerCore/Swift"),
        // The C++ sign-perception library behind SignDetector/include: unrolling, cascade, U-Net, slice
        // measurement, range estimation (src/range, wf_range.h) and the sign-kind catalogue.
        .target(
            name: "SignDetector",
            dependencies: ["WayfinderStatus"],
            path: "SignDetector",
            sources: ["src"],
            publicHeadersPath: "include",
            cxxSettings: cxxCoreFlags + [.headerSearchPath("src"), .headerSearchPath("src/range"),
                                         // placard text with Debian's tesseract (scripts/setup.sh); the iPhone reads it with Vision
                                         .define("WF_SIGN_DETECTOR_HAS_TEXT_READER", to: "1", .when(platforms: [.linux]))],
            linkerSettings: openCVLibraries + [.linkedLibrary("tesseract", .when(platforms: [.linux]))]
        ),
        // Swift wrapper over SignDetector: SignDetector (frame -> sightings), RangeEstimator, RangeCSV.
        .target(name: "SignDetection", dependencies: ["SignDetector", "Maps"], path: "SignDetector/Swift"),
        // Map model, format v1, validation, importers, bundled buildings.
        .target(
            name: "Maps",
            path: "Maps",
            exclude: ["schema"],  // the JSON schema is for people and other tools (read by path in MapLoaderTests)
            sources: ["Sources"],
            resources: [.copy("Buildings")]
        ),
        // Recorded-session bundle v1: one reader, one writer.
        .target(name: "SessionFormat", path: "App/SessionFormat"),
        // Routing, maneuvers, phrases and the announcement policy.
        .target(
            name: "Navigation",
            dependencies: ["Maps"],
            path: "Navigation",
            sources: ["Sources"],
            resources: [.copy("Locales")]
        ),
        // App logic shared by the iOS shell and the command line: frame -> detector -> localizer ->
        // navigator -> announcer.
        .target(
            name: "WayfinderCore",
            dependencies: ["Maps", "SessionFormat", "Localizer", "SignDetection", "Navigation"],
            path: "App/Core"
        ),
        // Walk simulator with known truth.
        .target(name: "Simulation", dependencies: ["Maps", "SessionFormat"], path: "App/Simulation"),
        // Scoring replays against truth, and the trainer's HTML/PNG picture of a walk.
        .target(
            name: "Evaluation",
            dependencies: ["WayfinderCore", "Simulation", "SessionFormat", "Maps", "Navigation"],
            path: "App/Evaluation"
        ),
        // The `wayfinder` command.
        .executableTarget(
            name: "WayfinderCLI",
            dependencies: ["WayfinderCore", "Simulation", "Evaluation", "Maps", "SessionFormat", "Localizer",
                           "SignDetection", "Navigation"],
            path: "App/CLI"
        ),
        // `wayfinder-fuzz`: mutation fuzzer of every file reader (docs/fuzzing.md).
        .executableTarget(name: "WayfinderFuzz", dependencies: ["Maps", "SessionFormat", "Localizer", "SignDetection"],
                         path: "App/Fuzz"),

        // The test targets' shared deterministic generator (Tests/TestRandom).
        .target(name: "TestRandom", path: "Tests/TestRandom"),
        .testTarget(name: "MapsTests", dependencies: ["Maps"], path: "Tests/MapsTests"),
        .testTarget(name: "SessionFormatTests", dependencies: ["TestRandom", "SessionFormat"], path: "Tests/SessionFormatTests"),
        .testTarget(name: "LocalizerTests", dependencies: ["TestRandom", "Localizer", "Maps"], path: "Tests/LocalizerTests"),
        .testTarget(name: "SignDetectionTests", dependencies: ["SignDetection", "Maps"], path: "Tests/SignDetectionTests"),
        .testTarget(name: "NavigationTests", dependencies: ["TestRandom", "Navigation", "Maps"], path: "Tests/NavigationTests"),
        .testTarget(name: "WayfinderCoreTests", dependencies: ["TestRandom", "WayfinderCore"], path: "Tests/WayfinderCoreTests"),
        .testTarget(name: "SimulationTests", dependencies: ["Simulation", "Maps", "SessionFormat"],
                    path: "Tests/SimulationTests"),
        .testTarget(name: "EvaluationTests", dependencies: ["Evaluation", "Simulation", "Maps", "SessionFormat"],
                    path: "Tests/EvaluationTests"),
        .testTarget(name: "CLITests", dependencies: ["TestRandom", "WayfinderCLI"], path: "Tests/CLITests"),
    ],
    cxxLanguageStandard: .cxx17
)
