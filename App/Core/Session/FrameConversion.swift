import Foundation
import SessionFormat
import SignDetection

/// The conversion logic of the iOS frame adapter, kept here so it is tested on Linux: the adapter in
/// App/iOS only reads ARKit's fields and passes plain numbers to these functions.
public enum FrameConversion {
    /// ARKit `simd_float4x4` columns (4 columns of 4 floats, as `transform.columns.0...3`) to the
    /// column-major 16 doubles of `FrameRecord.cameraToWorld`. Nil unless finite.
    public static func columnMajor(columns: [[Float]]) -> CameraPose? {
        guard columns.count == 4, columns.allSatisfy({ $0.count == 4 }) else { return nil }
        return CameraPose(columnMajor: columns.flatMap { $0.map(Double.init) })
    }

    /// ARKit's 3x3 intrinsics (`camera.intrinsics`, column-major columns: [fx,0,0], [0,fy,0], [cx,cy,1]) and
    /// image resolution to `CameraIntrinsics`. Nil when non-finite or non-positive.
    public static func intrinsics(columns: [[Float]], width: Int, height: Int) -> CameraIntrinsics? {
        guard columns.count == 3, columns.allSatisfy({ $0.count == 3 }), width > 0, height > 0 else { return nil }
        let fx = Double(columns[0][0]), fy = Double(columns[1][1]), cx = Double(columns[2][0]), cy = Double(columns[2][1])
        guard [fx, fy, cx, cy].allSatisfy({ $0.isFinite }), fx > 0, fy > 0 else { return nil }
        return CameraIntrinsics(fx: fx, fy: fy, cx: cx, cy: cy, width: width, height: height)
    }

    /// ARKit's tracking state as the adapter spells it (`normal`, `notAvailable`, `limited(reason)` with
    /// reason `initializing`, `excessiveMotion`, `insufficientFeatures`, `relocalizing`).
    public static func tracking(state: String, reason: String?) -> (TrackingState, TrackingReason?) {
        switch state {
        case "normal": return (.normal, nil)
        case "limited": return (.limited, reason.flatMap(TrackingReason.init(rawValue:)))
        default: return (.notAvailable, nil)
        }
    }

    /// Core Location's heading (degrees clockwise from north, negative when invalid) to the record's value.
    public static func compassHeadingDeg(_ heading: Double, accuracyDeg: Double) -> Double? {
        guard heading.isFinite, heading >= 0, accuracyDeg >= 0, accuracyDeg.isFinite else { return nil }
        return heading.truncatingRemainder(dividingBy: 360)
    }

    /// Builds the pipeline frame of one ARFrame's numbers (and, when the detector is due, its luma plane as
    /// `image`). A non-finite pose yields a frame with no pose (the pipeline skips its motion update and
    /// treats tracking as lost), never a crash.
    public static func pipelineFrame(t: Double, transformColumns: [[Float]], intrinsicsColumns: [[Float]],
                                     imageWidth: Int, imageHeight: Int, trackingState: String, trackingReason: String?,
                                     relativeAltitudeMeters: Double?, compassHeadingDeg: Double?,
                                     compassAccuracyDeg: Double? = nil,
                                     image: ImageBuffer? = nil) -> PipelineFrame? {
        guard t.isFinite, let k = intrinsics(columns: intrinsicsColumns, width: imageWidth, height: imageHeight) else { return nil }
        let pose = columnMajor(columns: transformColumns)
        let (state, reason) = tracking(state: trackingState, reason: trackingReason)
        var frame = PipelineFrame(t: t, cameraPose: pose, tracking: pose == nil ? .notAvailable : state,
                                  trackingReason: reason, intrinsics: k, relativeAltitudeMeters: relativeAltitudeMeters,
                                  compassHeadingDeg: compassHeadingDeg, image: image)
        // Core Location's accuracy: negative means invalid, beyond 180 degrees means nothing.
        if compassHeadingDeg != nil, let a = compassAccuracyDeg, a.isFinite, a >= 0, a <= 180 { frame.compassAccuracyDeg = a }
        return frame
    }

    /// The record written by the recorder for a pipeline frame (nil pose frames are not recorded).
    public static func record(of frame: PipelineFrame, imageName: String?) -> FrameRecord? {
        guard let pose = frame.cameraPose else { return nil }
        return FrameRecord(t: frame.t, cameraToWorld: pose.columnMajor, tracking: frame.tracking,
                           trackingReason: frame.trackingReason, intrinsics: frame.intrinsics,
                           relativeAltitudeMeters: frame.relativeAltitudeMeters, compassHeadingDeg: frame.compassHeadingDeg,
                           image: imageName, compassAccuracyDeg: frame.compassAccuracyDeg)
    }
}
