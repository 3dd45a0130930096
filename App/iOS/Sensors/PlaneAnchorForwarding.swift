#if canImport(ARKit) && os(iOS)
import ARKit
import SessionFormat
import WayfinderCore

/// ARPlaneAnchor add / update / remove events of `SensorHub`'s session, turned into `PlaneRecord`s by
/// `PlaneConversion.record` (plain numbers; tested on Linux) and handed to the `PipelineWorker` (never the
/// main queue), for the pipeline (scored against the walls at the next frame, as in replay) and the
/// recorder (planes.jsonl). Vertical planes only (the configuration asks for `.vertical` detection).
extension SensorHub {
    func session(_ session: ARSession, didAdd anchors: [ARAnchor]) { forward(anchors, event: .add, session: session) }

    func session(_ session: ARSession, didUpdate anchors: [ARAnchor]) { forward(anchors, event: .update, session: session) }

    func session(_ session: ARSession, didRemove anchors: [ARAnchor]) { forward(anchors, event: .remove, session: session) }

    private func forward(_ anchors: [ARAnchor], event: PlaneEvent, session: ARSession) {
        guard let t = session.currentFrame?.timestamp else { return }
        let records: [PlaneRecord] = anchors.compactMap { anchor in
            guard let plane = anchor as? ARPlaneAnchor, plane.alignment == .vertical else { return nil }
            let m = plane.transform
            let extent = plane.planeExtent
            return PlaneConversion.record(
                t: t, anchorId: plane.identifier.uuidString, event: event, vertical: true,
                transformColumns: [[m.columns.0.x, m.columns.0.y, m.columns.0.z, m.columns.0.w],
                                   [m.columns.1.x, m.columns.1.y, m.columns.1.z, m.columns.1.w],
                                   [m.columns.2.x, m.columns.2.y, m.columns.2.z, m.columns.2.w],
                                   [m.columns.3.x, m.columns.3.y, m.columns.3.z, m.columns.3.w]],
                centerLocal: [plane.center.x, plane.center.y, plane.center.z],
                extentWidth: extent.width, extentHeight: extent.height, rotationOnYAxisRad: extent.rotationOnYAxis,
                classification: ARPlaneAnchor.isClassificationSupported ? Self.describe(plane.classification) : nil)
        }
        guard !records.isEmpty else { return }
        worker.ingest(planes: records)
    }

    static func describe(_ c: ARPlaneAnchor.Classification) -> String {
        switch c {
        case .wall: return "wall"
        case .floor: return "floor"
        case .ceiling: return "ceiling"
        case .table: return "table"
        case .seat: return "seat"
        case .door: return "door"
        case .window: return "window"
        case .none: return "none"
        @unknown default: return "none"
        }
    }
}
#endif
