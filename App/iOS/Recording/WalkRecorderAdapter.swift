#if canImport(UIKit) && os(iOS)
import Foundation
import Maps
import SessionFormat
import UIKit
import WayfinderCore

/// Owns the `WalkRecorder` while "Record this walk" is on; bundles go to the app's Documents folder (visible
/// in Files) and the last one can be shared with the share sheet.
final class WalkRecorderAdapter {
    private var recorder: WalkRecorder?
    private(set) var lastBundleURL: URL?

    func start(building: Building, session: GuidanceSession) {
        let documents = FileManager.default.urls(for: .documentDirectory, in: .userDomainMask)[0]
        let url = documents.appendingPathComponent(WalkRecorder.folderName(for: Date()))
        let version = Bundle.main.object(forInfoDictionaryKey: "CFBundleShortVersionString") as? String ?? "0"
        recorder = try? WalkRecorder(directory: url, building: building, floorId: session.floorId, startId: session.startId,
                                     destinationId: session.destinationId, device: UIDevice.current.model, appVersion: version)
        lastBundleURL = url
    }

    func append(frame: PipelineFrame, jpeg: Data?) { try? recorder?.append(frame: frame, jpeg: jpeg) }

    func append(planes: [PlaneRecord]) { recorder?.append(planes: planes) }

    func stop() {
        try? recorder?.close()
        recorder = nil
    }
}
#endif
