import Simulation

/// The `--sim-detector NAME` option shared by `simulate` and `eval --scenarios`: which detector noise the
/// simulator gives its sightings. `standard` is docs/simulator.md's model; `real-unet` and `real-cascade` are
/// the detectors' errors measured on real photos (`DetectorParameters.realPhotoUNet`, `.realPhotoCascade`).
enum SimDetectorOption {
    /// Usage text for the option.
    static let usage = """
      --sim-detector   the simulated detector's noise: standard (docs/simulator.md, the default), real-unet or
                       real-cascade (the U-Net's and the unrefined cascade's errors measured on real photos:
                       range bias +6.8 % and -25 %, their recall and false positives)
    """

    /// Removes `--sim-detector` from `arguments` and returns the simulation parameters it names (the standard
    /// ones when absent), and whether it was given. Throws a usage error for an unknown name.
    static func parse(_ arguments: inout ArgumentList) throws -> (parameters: SimulationParameters, given: Bool) {
        var parameters = SimulationParameters.standard
        guard let name = try arguments.option("sim-detector") else { return (parameters, false) }
        switch name {
        case "standard": break
        case "real-unet": parameters.detector = .realPhotoUNet
        case "real-cascade": parameters.detector = .realPhotoCascade
        default: throw CLIError.usage("--sim-detector must be standard, real-unet or real-cascade, got '\(name)'")
        }
        return (parameters, true)
    }
}
