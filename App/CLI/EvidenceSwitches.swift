import WayfinderCore

/// The localizer's evidence switches shared by `replay` and `eval`: where sign sightings come from, each
/// evidence source can be turned off, and internal model parameters set by name, for studies
/// (docs/benchmarks.md "Evidence sources", "End to end with the detectors").
enum EvidenceSwitches {
    /// Usage lines for the subcommands that accept the switches.
    static let usage = """
      --detector       where sign sightings come from: recorded, cascade, unet or auto (default: the detector
                       on the images when any is present, a frame whose image is missing using its recorded
                       observations; else the recorded observations)
      --models DIR     detector models folder (default SignDetector/models)
      --no-compass     ignore the compass (no start prior, no compass evidence)
      --no-planes      ignore ARKit's vertical planes (planes.jsonl; simulated walls in --scenarios)
      --no-north-check keep using the compass when it reads 60 degrees or more off the localized heading over
                       15 m walked (by default the map's north is then reported as suspect and the compass
                       evidence stops; docs/localizer.md "The north check")
      --wall-kinds M   which wall kinds (pictograms, placards) each detector frame looks for, within the phone
                       detector's budget of two kinds on every second frame: expected (the default, the phone's:
                       the kind the hypotheses expect in view first, the other in turn), rotation (in turn only)
                       or every-frame (all of them, no budget). Given, it also applies to recorded observations
                       (a study of the phone's budget on simulated walks): a sighting of a kind the frame does
                       not look for is left out (docs/sign-detection.md "Which wall kinds a frame looks for")
      --no-corroboration  count every sighting in full, even one no earlier detector frame saw at about the
                       same place of the VIO plane (by default such a sighting counts at a quarter of its score:
                       docs/localizer.md "Corroborated sightings")
      --corroboration F  the factor on an uncorroborated sighting's score instead of 0.25 (1 = off)
      --repeat-factor F  while not localized, the factor on the score of an object's sighting repeated from where
                       the camera stood (under 5 cm from its last full-weight one, within 1 s) instead of 0.25
                       (1 = off; docs/localizer.md "Corroborated sightings")
      --recount-unexplained M  while localized, an object seen again that the locked pose does not explain
                       counts once per M meters walked instead of 1 (0 = every frame)
      --no-track-objects  count every sighting on its own, even the sightings of one object tracked on the VIO
                       plane (by default they count as one object's: what a look-alike watched for seconds can
                       say against a pose is bounded; docs/localizer.md "Tracked objects"; the same as
                       --param track.enabled=0). --track-objects asks for the default explicitly
      --param NAME=V   set an internal localizer parameter (e.g. compass.kappa=8; see docs/localizer.md);
                       may be repeated
    """

    /// Removes the switches from `arguments` and applies them to `options`. Throws a usage error for a
    /// malformed `--param`.
    static func apply(_ arguments: inout ArgumentList, to options: inout PipelineOptions) throws {
        if let d = try arguments.option("detector") {
            guard let source = SightingSource(rawValue: d == "auto" ? "automatic" : d) else {
                throw CLIError.usage("--detector must be recorded, cascade, unet or auto")
            }
            options.sightingSource = source
        }
        if let models = try arguments.option("models") { options.modelsDirectory = models }
        if arguments.flag("no-compass") { options.useCompass = false }
        if arguments.flag("no-planes") { options.usePlanes = false }
        if arguments.flag("no-north-check") { options.compassNorthCheck = nil }
        if arguments.flag("no-corroboration") { options.sightingCorroboration.uncorroboratedScoreFactor = 1 }
        if let f = try arguments.option("corroboration") {
            guard let factor = Double(f), (0...1).contains(factor) else {
                throw CLIError.usage("--corroboration wants a factor in 0...1, got '\(f)'")
            }
            options.sightingCorroboration.uncorroboratedScoreFactor = factor
        }
        if let f = try arguments.option("repeat-factor") {
            guard let factor = Double(f), (0...1).contains(factor) else {
                throw CLIError.usage("--repeat-factor wants a factor in 0...1, got '\(f)'")
            }
            options.sightingCorroboration.stationaryRepeatScoreFactor = factor
        }
        if let r = try arguments.option("recount-unexplained") {
            guard let meters = Double(r), meters.isFinite, meters >= 0 else {
                throw CLIError.usage("--recount-unexplained wants meters >= 0, got '\(r)'")
            }
            options.sightingCorroboration.unexplainedObjectRecountMeters = meters
        }
        if let m = try arguments.option("wall-kinds") {
            guard let mode = WallKindScheduler.Mode(rawValue: m) else {
                throw CLIError.usage("--wall-kinds must be expected, rotation or every-frame")
            }
            options.wallKindSchedule = mode
            options.scheduleRecordedSightings = true
        }
        if arguments.flag("track-objects") { options.localizerParameters["track.enabled"] = 1 }
        if arguments.flag("no-track-objects") { options.localizerParameters["track.enabled"] = 0 }
        while let assignment = try arguments.option("param") {
            let parts = assignment.split(separator: "=", maxSplits: 1).map(String.init)
            guard parts.count == 2, !parts[0].isEmpty, let value = Double(parts[1]), value.isFinite else {
                throw CLIError.usage("--param wants NAME=NUMBER, got '\(assignment)'")
            }
            options.localizerParameters[parts[0]] = value
        }
    }
}
