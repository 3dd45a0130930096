import Foundation
import Localizer
import Maps
import SessionFormat
import SignDetection

/// One frame's sightings and the sign kinds the frame did not look for (the detector searches its wall kinds in
/// turn, and a skipped frame looks for none): the localizer takes no negative information for those kinds.
struct FrameSightings {
    /// The sightings, as measured.
    var sightings: [SignSighting]
    /// Kinds not looked for on this frame; for recorded observations, the frame's `unsearchedSignKinds` (empty in
    /// older bundles: every kind counts as searched).
    var unsearchedKinds: Set<String> = []
}

/// Produces the sign sightings of a frame: either the recorded (already measured) observations, or the sign
/// perception run on the frame's image: one C call per frame (`SignDetector.sense`: detection, slices and the
/// apparent-height range with each kind's face height from the map's sign-kind catalogue).
///
/// With `.automatic` and a detector loaded, a frame that carries no image but does carry recorded
/// observations gets those (replay passes them only for frames whose named image is missing: "a missing
/// image falls back to the frame's recorded observations"). The explicit `.cascade` / `.unet` never mix
/// in recorded observations.
final class SignSightingSource {
    private let options: PipelineOptions
    private let detector: SignDetector?
    /// Kinds of the catalogue whose legend is read (`SignKindSpec.readsText`).
    private let textKinds: Set<String>
    /// The kinds searched in turn (`WallKindScheduler`): the detector's wall kinds when it runs here; for recorded
    /// observations, those the phone's detector has: every kind of the catalogue but the U-Net's class (the Exit
    /// sign), whose cascades run beside it.
    let wallKinds: [String]
    /// Whether the frames' wall kinds are chosen here (`WallKindScheduler`): a detector runs, or recorded observations
    /// go through the schedule (`PipelineOptions.scheduleRecordedSightings`).
    var schedulesWallKinds: Bool { !wallKinds.isEmpty && (detector != nil || options.scheduleRecordedSightings) }

    /// Loads the detector when images will be processed, with the sign sizes of `catalogue` (the map's
    /// `Building.signCatalogue` unless `options.signCatalogue` overrides it). Throws when its model is missing.
    init(options: PipelineOptions, catalogue: SignCatalogue, imagesAvailable: Bool) throws {
        self.options = options
        textKinds = Set((options.signCatalogue ?? catalogue).kinds.filter(\.readsText).map(\.kind))
        let kind: DetectorKind?
        switch options.sightingSource {
        case .recorded: kind = nil
        case .cascade: kind = .cascade
        case .unet: kind = .unet
        case .automatic: kind = imagesAvailable ? .unet : nil
        }
        if let kind {
            do {
                detector = try SignDetector(configuration: DetectorConfiguration.bundled(
                    kind: kind, modelsDirectory: options.modelsDirectory, catalogue: options.signCatalogue ?? catalogue))
            } catch {
                throw PipelineError.invalidConfiguration("cannot load the \(kind.rawValue) sign detector: \(error)")
            }
        } else {
            detector = nil
        }
        wallKinds = detector?.wallKinds
            ?? (options.signCatalogue ?? catalogue).kinds.map(\.kind).filter { $0 != SignKindSpec.defaultExit.kind }
    }

    /// The sightings of `frame` and the kinds it did not look for; `.success(nil)` when there was nothing to consult
    /// on this frame (no image and no recorded observations while recorded observations are in use).
    /// `searchedWallKinds`: the wall kinds this frame looks for (`WallKindScheduler`); nil: the detector's own
    /// schedule. Recorded sightings of the other wall kinds are left out only with
    /// `PipelineOptions.scheduleRecordedSightings` (the phone's detector would not have found them).
    func sightings(for frame: PipelineFrame, pose: CameraPose,
                   searchedWallKinds: Set<String>? = nil) -> Result<FrameSightings?, PipelineError> {
        let recordedSchedule = options.scheduleRecordedSightings ? searchedWallKinds : nil
        guard let detector else { return .success(recorded(frame, searchedWallKinds: recordedSchedule)) }
        guard frame.image != nil || frame.imagePath != nil else {
            if options.sightingSource == .automatic, !frame.measuredObservations.isEmpty {
                return .success(recorded(frame, searchedWallKinds: recordedSchedule))
            }
            return .success(nil)
        }
        let source = frame.imagePath ?? "camera frame"
        do {
            let image = try frame.image ?? ImageBuffer.load(path: frame.imagePath!)
            if let searchedWallKinds { try detector.requestWallKinds(searchedWallKinds.intersection(wallKinds)) }
            let k = frame.intrinsics
            let sensed = try detector.senseFrame(image: image, fx: k.fx, fy: k.fy, cx: k.cx, cy: k.cy,
                                                 pitchRad: pose.pitchRad, rollRad: pose.rollRad)
            let sightings = sensed.signs.map { s -> SignSighting in
                // The detector's reading, else the platform's (Vision on the iPhone) for kinds that read text.
                var text = s.text
                if text == nil, textKinds.contains(s.kind), let read = options.legendReader {
                    text = read(image, s.cornersRaw).flatMap(Self.cleanLegend)
                }
                return SignSighting(kind: s.kind, rangeMeters: s.rangeMeters, bearingRad: s.bearingRad, score: s.score,
                                    text: text)
            }
            return .success(FrameSightings(sightings: sightings, unsearchedKinds: sensed.unsearchedKinds))
        } catch {
            return .failure(.frame("image \(source): \(error)"))
        }
    }

    /// `raw` upper-cased and reduced to letters, digits and '-' (the detector's rule for legends; O and I, which
    /// room numbers do not use, read as 0 and 1), nil when nothing is left or it is longer than 15 characters.
    static func cleanLegend(_ raw: String) -> String? {
        let mapped = raw.uppercased().replacingOccurrences(of: "O", with: "0").replacingOccurrences(of: "I", with: "1")
        let kept = String(mapped.unicodeScalars.filter {
            ("A"..."Z").contains($0) || ("0"..."9").contains($0) || $0 == "-"
        }.map(Character.init)).trimmingCharacters(in: CharacterSet(charactersIn: "-"))
        return kept.isEmpty || kept.count > 15 ? nil : kept
    }

    /// The frame's recorded observations and the kinds its recording detector did not look for, less the wall kinds
    /// this frame does not look for (`searchedWallKinds`, nil: all of them), which join the unsearched kinds.
    private func recorded(_ frame: PipelineFrame, searchedWallKinds: Set<String>?) -> FrameSightings {
        var unsearched = frame.unsearchedSignKinds
        if let searchedWallKinds { unsearched.formUnion(Set(wallKinds).subtracting(searchedWallKinds)) }
        return FrameSightings(sightings: recordedSightings(frame).filter { !unsearched.contains($0.kind) },
                              unsearchedKinds: unsearched)
    }

    /// The frame's recorded observations as sightings, skipping any with a range that is not finite, not
    /// positive or beyond `ObservationRecord.maximumRangeMeters` (the reader already drops those from files),
    /// or a bearing that is not finite.
    private func recordedSightings(_ frame: PipelineFrame) -> [SignSighting] {
        frame.measuredObservations.compactMap { o -> SignSighting? in
            guard o.rangeMeters.isFinite, o.rangeMeters > 0, o.rangeMeters <= ObservationRecord.maximumRangeMeters,
                  o.bearingRad.isFinite else { return nil }
            return SignSighting(kind: o.kind, rangeMeters: o.rangeMeters, bearingRad: o.bearingRad, score: o.score,
                                text: o.text)
        }
    }
}
