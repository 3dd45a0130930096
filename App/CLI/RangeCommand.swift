import Foundation
import Localizer
import SignDetection

/// `wayfinder range`: range and bearing to signs from a CSV of corner observations, by every method, with
/// the percent error when the true range is known. Method details: docs/range-estimation.md.
enum RangeCommand: Subcommand {
    static let name = "range"
    static let summary = "Range and bearing to signs from corner observations (apparent height, horizon, PnP)"
    static let usage = """
    Usage: wayfinder range --input obs.csv [--method apparent-height|horizon|pnp|all]

    Estimates the horizontal range (m) and bearing (deg, positive left) to a rectangular sign of known size
    from its four corners in the raw camera image, by the chosen method (default: all), and prints a CSV to
    stdout, one line per observation and method:
      line,method,range_m,bearing_deg,center_height_above_camera_m,true_range_m,error_pct,status
    error_pct = 100 |estimate - true| / true when true_range_m is given; status is "ok" or why the method
    gave no estimate. A median error per method goes to stderr.

    Input CSV (header required, columns in any order, '#' lines and blank lines skipped):
      image_width,image_height   raw image size, pixels
      fx,fy,cx,cy                raw intrinsics, pixels
      pitch_rad,roll_rad         camera pitch (+ up) and roll (0 landscape, -pi/2 portrait), or instead
      camera_to_world            16 ';'-separated numbers, column-major 4x4 (ARKit), used when present
      u_tl,v_tl,u_tr,v_tr,u_br,v_br,u_bl,v_bl
                                 raw-image corners of the upright sign: top-left, top-right, bottom-right,
                                 bottom-left (clockwise on screen), pixels
      sign_height_m              sign face height, meters
      sign_width_m               optional; needed by pnp
      camera_height_m,sign_center_height_m
                                 optional, heights above the floor in meters; needed by horizon
      true_range_m               optional; adds the percent error

    Methods: apparent-height (h0 / (tan e_top - tan e_bottom), exact for any roll), horizon ((sign centre
    height - camera height) / tan e_centre), pnp (OpenCV solvePnP on the corners). With --method all, a
    method whose optional columns are empty on a row is reported as skipped; naming it explicitly makes
    missing columns an error.

    Example: wayfinder range --input Tests/Fixtures/range/observations.csv
    Exit codes: 0 every requested estimate succeeded, 1 some failed or the input is bad, 2 usage.
    """

    static func run(_ arguments: inout ArgumentList) throws -> Int32 {
        let input = try arguments.requiredOption("input")
        let methodName = try arguments.option("method") ?? "all"
        let leftovers = try arguments.positionals()
        guard leftovers.isEmpty else { throw CLIError.usage("unexpected argument '\(leftovers[0])'") }
        let methods: [RangeMethod]
        if methodName == "all" {
            methods = RangeMethod.allCases
        } else if let m = RangeMethod(commandLineName: methodName) {
            methods = [m]
        } else {
            throw CLIError.usage("--method must be apparent-height, horizon, pnp or all, got '\(methodName)'")
        }
        let explicit = methods.count == 1

        let rows: [RangeObservationRow]
        do {
            rows = try RangeCSV.read(path: input)
        } catch let error as RangeCSVError {
            throw CLIError.failure(error.description)
        }
        if rows.isEmpty { note("wayfinder range: \(input) has no observations") }

        var output = "line,method,range_m,bearing_deg,center_height_above_camera_m,true_range_m,error_pct,status\n"
        var errorsByMethod: [RangeMethod: [Double]] = [:]
        var failures = 0
        for row in rows {
            for method in methods {
                let truth = row.trueRangeMeters.map { fmt($0, 3) } ?? ""
                if let missing = missingInput(method, row) {
                    if explicit {
                        throw CLIError.failure("\(input):\(row.lineNumber): \(method.commandLineName) needs \(missing)")
                    }
                    output += "\(row.lineNumber),\(method.commandLineName),,,,\(truth),,skipped: no \(missing)\n"
                    continue
                }
                do {
                    let e = try row.estimate(method)
                    var errorText = ""
                    if let t = row.trueRangeMeters {
                        let pct = 100 * abs(e.rangeMeters - t) / t
                        errorsByMethod[method, default: []].append(pct)
                        errorText = fmt(pct, 2)
                    }
                    output += "\(row.lineNumber),\(method.commandLineName),\(fmt(e.rangeMeters, 4)),"
                        + "\(fmt(e.bearingRad * 180 / .pi, 3)),\(fmt(e.centerHeightAboveCameraMeters, 3)),"
                        + "\(truth),\(errorText),ok\n"
                } catch let error as RangeEstimationError {
                    failures += 1
                    note("wayfinder range: \(input):\(row.lineNumber): \(method.commandLineName): \(error)")
                    output += "\(row.lineNumber),\(method.commandLineName),,,,\(truth),,\(csvField("error: \(error)"))\n"
                }
            }
        }
        print(output, terminator: "")
        for method in methods {
            guard let errors = errorsByMethod[method], !errors.isEmpty else { continue }
            let sorted = errors.sorted()
            let median = sorted.count % 2 == 1 ? sorted[sorted.count / 2]
                : 0.5 * (sorted[sorted.count / 2 - 1] + sorted[sorted.count / 2])
            note("wayfinder range: \(method.commandLineName): median error \(fmt(median, 2)) % over \(errors.count) observations")
        }
        return failures == 0 ? 0 : 1
    }

    /// The optional input a method needs and the row lacks, named by column; nil when complete.
    private static func missingInput(_ method: RangeMethod, _ row: RangeObservationRow) -> String? {
        switch method {
        case .apparentHeight: return nil
        case .pnp: return row.signWidthMeters == nil ? "sign_width_m" : nil
        case .horizon:
            if row.cameraHeightMeters == nil { return "camera_height_m" }
            return row.signCenterHeightMeters == nil ? "sign_center_height_m" : nil
        }
    }

    private static func fmt(_ v: Double, _ decimals: Int) -> String { String(format: "%.\(decimals)f", v) }

    /// Quotes a CSV field that contains a comma or quote.
    private static func csvField(_ s: String) -> String {
        guard s.contains(",") || s.contains("\"") else { return s }
        return "\"" + s.replacingOccurrences(of: "\"", with: "\"\"") + "\""
    }
}
