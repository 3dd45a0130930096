import Foundation

/// What `wayfinder inspect` reports about a bundle; Codable for `--json`.
public struct BundleSummary: Codable, Hashable, Sendable {
    /// session.json's formatVersion.
    public var formatVersion: Int
    /// Recording device.
    public var device: String
    /// App or tool that wrote it.
    public var appVersion: String
    /// Building map id, if known.
    public var mapId: String?
    /// Starting floor id, if known.
    public var floorId: String?
    /// Origin of imported recordings.
    public var source: String?
    /// Time from the first to the last frame, seconds.
    public var durationSeconds: Double
    /// Number of frames.
    public var frameCount: Int
    /// Mean frame rate, (frames - 1) / duration, Hz (0 for a single frame).
    public var frameRateHz: Double
    /// Share of frames per tracking state (`normal`...), 0...1; states that never occur are absent.
    public var trackingShare: [String: Double]
    /// Length of the camera's path in the ARKit world, 3-D, meters (sum of frame-to-frame steps).
    public var pathLengthMeters: Double
    /// Number of observations.
    public var observationCount: Int
    /// Observations per kind (`exit`, `landmark`...).
    public var observationsByKind: [String: Int]
    /// Distinct landmark ids among the observations.
    public var distinctLandmarkCount: Int
    /// Number of truth poses (0 = no truth.jsonl).
    public var truthCount: Int
    /// True when the bundle has truth.jsonl lines.
    public var hasTruth: Bool
    /// Number of expected announcements.
    public var expectedCount: Int
    /// Frames naming an image.
    public var framesWithImage: Int
    /// Files in images/.
    public var imageFileCount: Int
    /// The reader's warnings, as text.
    public var warnings: [String]
}

extension SessionBundle {
    /// Summarises the bundle (counts the files in images/ on disk).
    public func summary() -> BundleSummary {
        let duration = (frames.last?.t ?? 0) - (frames.first?.t ?? 0)
        var tracking: [String: Int] = [:]
        for f in frames { tracking[f.tracking.rawValue, default: 0] += 1 }
        var path = 0.0
        for (a, b) in zip(frames, frames.dropFirst()) {
            let p = a.cameraToWorld, q = b.cameraToWorld
            path += ((q[12] - p[12]) * (q[12] - p[12]) + (q[13] - p[13]) * (q[13] - p[13])
                + (q[14] - p[14]) * (q[14] - p[14])).squareRoot()
        }
        var byKind: [String: Int] = [:]
        for o in observations { byKind[o.kind, default: 0] += 1 }
        let imageFiles = (try? FileManager.default.contentsOfDirectory(atPath: imagesDirectory.path))?
            .filter { !$0.hasPrefix(".") }.count ?? 0
        return BundleSummary(
            formatVersion: info.formatVersion, device: info.device, appVersion: info.appVersion, mapId: info.mapId,
            floorId: info.floorId, source: info.source, durationSeconds: duration, frameCount: frames.count,
            frameRateHz: duration > 0 ? Double(frames.count - 1) / duration : 0,
            trackingShare: tracking.mapValues { Double($0) / Double(max(1, frames.count)) },
            pathLengthMeters: path, observationCount: observations.count, observationsByKind: byKind,
            distinctLandmarkCount: Set(observations.compactMap(\.landmarkId)).count,
            truthCount: truth.count, hasTruth: !truth.isEmpty, expectedCount: expected.count,
            framesWithImage: frames.filter { $0.image != nil }.count, imageFileCount: imageFiles,
            warnings: warnings.map(\.description))
    }
}

extension BundleSummary {
    /// Human-readable multi-line text (what `wayfinder inspect` prints without `--json`).
    public var text: String {
        func f(_ v: Double, _ digits: Int) -> String { String(format: "%.\(digits)f", v) }
        var lines: [String] = []
        lines.append("format version   \(formatVersion)")
        lines.append("device           \(device) (\(appVersion))")
        lines.append("map              \(mapId ?? "-")\(floorId.map { ", floor \($0)" } ?? "")")
        if let source { lines.append("source           \(source)") }
        lines.append("duration         \(f(durationSeconds, 1)) s")
        lines.append("frames           \(frameCount) at \(f(frameRateHz, 2)) Hz, path \(f(pathLengthMeters, 1)) m")
        let share = trackingShare.sorted { $0.key < $1.key }.map { "\($0.key) \(f($0.value * 100, 1))%" }
        lines.append("tracking         \(share.joined(separator: ", "))")
        let kinds = observationsByKind.sorted { $0.key < $1.key }.map { "\($0.key) \($0.value)" }
        lines.append("observations     \(observationCount)\(kinds.isEmpty ? "" : " (\(kinds.joined(separator: ", ")))")"
            + "\(distinctLandmarkCount > 0 ? ", \(distinctLandmarkCount) distinct landmarks" : "")")
        lines.append("truth            \(hasTruth ? "\(truthCount) poses" : "none")")
        lines.append("expected         \(expectedCount) announcements")
        lines.append("images           \(imageFileCount) files, \(framesWithImage) frames name one")
        lines.append("warnings         \(warnings.isEmpty ? "none" : String(warnings.count))")
        for w in warnings { lines.append("  - \(w)") }
        return lines.joined(separator: "\n")
    }
}
