import Foundation
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
      --sim-range-bias F  replaces that detector's systematic range error: measured = true x (1 + F), F > -1
                       (-0.12 = reads 12 % short; a study of how much bias the localizer holds behind)
      --sim-params FILE   lays a JSON object of noise-model parameters over those (keys of SimulationParameters,
                       e.g. {"vio": {"scaleErrorRange": [0.03, 0.1]}}; Tests/StressProfiles): walks behind noise
                       models other than the simulator's defaults. Applied after --sim-detector, before
                       --sim-range-bias
    """

    /// Removes `--sim-detector`, `--sim-params` and `--sim-range-bias` from `arguments` and returns the
    /// simulation parameters they name (the standard ones when absent), and whether any was given. Throws a usage
    /// error for an unknown name or a bias that is not a finite number above -1, and a failure naming the file
    /// for a parameter file that cannot be read or applied (`SimulationParametersOverlay`).
    static func parse(_ arguments: inout ArgumentList) throws -> (parameters: SimulationParameters, given: Bool) {
        var parameters = SimulationParameters.standard
        let name = try arguments.option("sim-detector")
        switch name {
        case nil, "standard": break
        case "real-unet": parameters.detector = .realPhotoUNet
        case "real-cascade": parameters.detector = .realPhotoCascade
        default: throw CLIError.usage("--sim-detector must be standard, real-unet or real-cascade, got '\(name ?? "")'")
        }
        let paramsPath = try arguments.option("sim-params")
        if let paramsPath {
            let data: Data
            do { data = try Data(contentsOf: URL(fileURLWithPath: paramsPath)) } catch {
                throw CLIError.failure("\(paramsPath): cannot read: \(error.localizedDescription)")
            }
            do { parameters = try SimulationParametersOverlay.apply(data, to: parameters) } catch {
                throw CLIError.failure("\(paramsPath): \(error)")
            }
        }
        let bias = try arguments.option("sim-range-bias")
        if let bias {
            guard let value = Double(bias), value.isFinite, value > -1 else {
                throw CLIError.usage("--sim-range-bias must be a number above -1 (a relative range error), got '\(bias)'")
            }
            parameters.detector.rangeBias = value
        }
        return (parameters, name != nil || bias != nil || paramsPath != nil)
    }
}
