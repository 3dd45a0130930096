// The only file of the SignDetection module that touches the C ABI (SignDetector/include/wf_sign_detector.h).
import Foundation
import Maps
internal import SignDetector

/// Owns a wf_detector handle; converts Swift values to C and C statuses to SignDetectorError.
final class CDetector {
    private var handle: OpaquePointer?
    let kinds: [String]

    /// Most observations returned per frame.
    static let capacity = 64

    init(configuration c: DetectorConfiguration) throws {
        var opts = wf_detector_options()
        guard wf_detector_options_init(&opts) == WF_STATUS_OK else {
            throw CDetector.error(status: WF_STATUS_INTERNAL, message: String(cString: wf_thread_last_error()))
        }
        opts.kind = c.kind == .cascade ? WF_DETECTOR_CASCADE : WF_DETECTOR_UNET
        opts.cascade_scale_factor = c.cascadeScaleFactor
        opts.cascade_min_neighbors = Int32(clamping: c.cascadeMinNeighbors)
        opts.cascade_min_window_width = Int32(clamping: c.cascadeMinWindowWidth)
        opts.cascade_min_window_height = Int32(clamping: c.cascadeMinWindowHeight)
        opts.cascade_max_window_factor = c.cascadeMaxWindowFactor
        opts.cascade_search_above_elevation = c.cascadeMinElevationRad == nil ? -1 : 1
        opts.cascade_min_elevation_rad = c.cascadeMinElevationRad ?? 0
        opts.cascade_placement_prior = c.cascadeSignAboveCameraMeters == nil ? -1 : 1
        // 0 means "the C default" there: a bound of exactly 0 m (a sign centred at camera height) is sent as 1 nm.
        func bound(_ metres: Double?) -> Double { metres.map { $0 == 0 ? 1e-9 : $0 } ?? 0 }
        opts.cascade_sign_above_camera_min_m = bound(c.cascadeSignAboveCameraMeters?.lowerBound)
        opts.cascade_sign_above_camera_max_m = bound(c.cascadeSignAboveCameraMeters?.upperBound)
        opts.cascade_gate_crowded_contrast_factor = c.cascadeGateCrowdedContrastFactor
        opts.cascade_gate_min_margin_px = Int32(clamping: c.cascadeGateMinMarginPixels)
        opts.cascade_gate_component_window_fraction = c.cascadeGateComponentWindowFraction ?? -1  // -1: off
        opts.unet_mask_threshold = c.unetMaskThreshold
        opts.unet_zoom_factor = c.unetZoomFactor
        opts.unet_min_crop_px = Int32(clamping: c.unetMinCropPx)
        opts.unet_max_candidates = Int32(clamping: c.unetMaxCandidates)
        opts.unet_coarse_min_elevation_rad = c.unetCoarseMinElevationRad ?? -2  // <= -1.5: no cut
        opts.min_score = c.minScore
        opts.slice_count = Int32(clamping: c.sliceCount)
        opts.slice_band_fraction = c.sliceBandFraction
        opts.roll_snap_tolerance_rad = c.rollSnapToleranceRad

        // C strings live until wf_detector_create returns (the C side copies them).
        let cascadePaths = c.cascades.map { strdup($0.path) }
        let cascadeKinds = c.cascades.map { strdup($0.kind) }
        let classNames = c.classNames.map { strdup($0) }
        let unetPath = c.unetPath.map { strdup($0) } ?? nil
        let catalogueStrings = c.catalogue.kinds.map { k in (strdup(k.kind), k.faceColor.map { strdup($0) } ?? nil,
                                                             k.legendColor.map { strdup($0) } ?? nil) }
        defer {
            (cascadePaths + cascadeKinds + classNames).forEach { free($0) }
            free(unetPath)
            catalogueStrings.forEach { free($0.0); free($0.1); free($0.2) }
        }
        var catalogue = zip(c.catalogue.kinds, catalogueStrings).map { k, strings in
            let band = DetectorConfiguration.placementBand(k)
            return wf_sign_kind(kind: UnsafePointer(strings.0), face_height_m: k.heightMeters, face_width_m: k.widthMeters,
                                face_colour: UnsafePointer(strings.1), legend_colour: UnsafePointer(strings.2),
                                double_sided: k.doubleSided ? 1 : 0,
                                centre_above_camera_min_m: band?.lowerBound ?? 0, centre_above_camera_max_m: band?.upperBound ?? 0,
                                max_range_m: k.maxRangeMeters ?? 0, reads_text: k.readsText ? 1 : 0)
        }
        var pathPointers = cascadePaths.map { UnsafePointer<CChar>($0) }
        var kindPointers = cascadeKinds.map { UnsafePointer<CChar>($0) }
        var classPointers = classNames.map { UnsafePointer<CChar>($0) }
        opts.unet_path = UnsafePointer(unetPath)
        var created: OpaquePointer?
        let status: Int32 = pathPointers.withUnsafeMutableBufferPointer { paths in
            kindPointers.withUnsafeMutableBufferPointer { kinds in
                classPointers.withUnsafeMutableBufferPointer { classes in
                  catalogue.withUnsafeMutableBufferPointer { entries in
                    opts.catalogue = UnsafePointer(entries.baseAddress)
                    opts.catalogue_count = entries.count
                    opts.cascade_paths = UnsafePointer(paths.baseAddress)
                    opts.cascade_kinds = UnsafePointer(kinds.baseAddress)
                    opts.cascade_count = paths.count
                    opts.class_names = UnsafePointer(classes.baseAddress)
                    opts.class_count = classes.count
                    return wf_detector_create(&created, &opts)
                  }
                }
            }
        }
        guard status == WF_STATUS_OK, let created else {
            throw CDetector.error(status: status, message: String(cString: wf_thread_last_error()))
        }
        handle = created
        let names = (0..<wf_detector_kind_count(created)).map { String(cString: wf_detector_kind_name(created, $0)) }
        kinds = names
        wallKinds = names.indices.filter { wf_detector_is_wall_kind(created, $0) == 1 }.map { names[$0] }
    }

    /// The kinds searched in turn (wf_detector_is_wall_kind), in the detector's order.
    let wallKinds: [String]

    /// wf_detector_request_wall_kinds for the named kinds (in the detector's kind order).
    func requestWallKinds(_ names: Set<String>) throws {
        let indices = kinds.indices.filter { names.contains(kinds[$0]) }
        if let unknown = names.subtracting(kinds).sorted().first {
            throw SignDetectorError.invalidArgument("the detector has no kind '\(unknown)'")
        }
        let status = indices.withUnsafeBufferPointer { wf_detector_request_wall_kinds(handle, $0.baseAddress, $0.count) }
        if status != WF_STATUS_OK {
            throw CDetector.error(status: status, message: String(cString: wf_detector_last_error(handle)))
        }
    }

    deinit { wf_detector_free(handle) }

    /// Calls `body` with a wf_frame borrowing the image's bytes (valid only during the call).
    private static func withFrame<R>(image: ImageBuffer, intrinsics: (Double, Double, Double, Double), pitchRad: Double,
                                     rollRad: Double, _ body: (inout wf_frame) -> R) -> R {
        image.data.withUnsafeBufferPointer { pixels in
            let chroma = image.chromaData ?? []
            return chroma.withUnsafeBufferPointer { chromaPixels in
                var frame = wf_frame()
                frame.image = wf_image(
                    data: pixels.baseAddress, width: Int32(clamping: image.width), height: Int32(clamping: image.height),
                    stride: image.bytesPerRow, format: CDetector.format(image.pixelFormat),
                    data_uv: image.chromaData == nil ? nil : chromaPixels.baseAddress,
                    stride_uv: image.chromaBytesPerRow, data_bytes: pixels.count,
                    data_uv_bytes: image.chromaData == nil ? 0 : chromaPixels.count)
                frame.intrinsics = wf_intrinsics(fx: intrinsics.0, fy: intrinsics.1, cx: intrinsics.2, cy: intrinsics.3)
                frame.pitch_rad = pitchRad
                frame.roll_rad = rollRad
                return body(&frame)
            }
        }
    }

    func detect(image: ImageBuffer, intrinsics: (Double, Double, Double, Double), pitchRad: Double,
                rollRad: Double) throws -> DetectionOutcome {
        let (found, warning) = try call(image: image, intrinsics: intrinsics, pitchRad: pitchRad, rollRad: rollRad,
                                        empty: wf_detector_observation(), wf_detector_detect)
        return DetectionOutcome(detections: found.map(CDetector.detection), warning: warning)
    }

    /// One wf_detector_sense call: the frame's ranged sightings, and the warning of a skipped frame.
    func sense(image: ImageBuffer, intrinsics: (Double, Double, Double, Double), pitchRad: Double,
               rollRad: Double) throws -> (signs: [SensedSign], warning: String?) {
        let (found, warning) = try call(image: image, intrinsics: intrinsics, pitchRad: pitchRad, rollRad: rollRad,
                                        empty: wf_sign_sighting(), wf_detector_sense)
        return (found.map(CDetector.sensed), warning)
    }

    /// The kinds the last frame did not look for (wf_detector_kind_searched): rejected frames, wall kinds whose
    /// turn had not come.
    var unsearchedKinds: Set<String> {
        Set(kinds.indices.filter { wf_detector_kind_searched(handle, $0) != 1 }.map { kinds[$0] })
    }

    /// One per-frame C call (`wf_detector_detect` or `wf_detector_sense`) into a buffer of `capacity` results:
    /// the results written, and the warning when the status is positive (a skipped frame). A negative status
    /// throws the detector's error.
    private func call<T>(image: ImageBuffer, intrinsics: (Double, Double, Double, Double), pitchRad: Double,
                         rollRad: Double, empty: T,
                         _ fn: (OpaquePointer?, UnsafePointer<wf_frame>?, UnsafeMutablePointer<T>?, Int,
                                UnsafeMutablePointer<Int>?) -> Int32) throws -> ([T], String?) {
        var results = [T](repeating: empty, count: CDetector.capacity)
        var count = 0
        let status: Int32 = CDetector.withFrame(image: image, intrinsics: intrinsics, pitchRad: pitchRad,
                                                rollRad: rollRad) { frame in
            results.withUnsafeMutableBufferPointer { out in fn(handle, &frame, out.baseAddress, out.count, &count) }
        }
        if status < 0 {
            throw CDetector.error(status: status, message: String(cString: wf_detector_last_error(handle)))
        }
        let warning = status > 0 ? String(cString: wf_detector_last_error(handle)) : nil
        return (Array(results.prefix(count)), warning)
    }

    private static func sensed(_ g: wf_sign_sighting) -> SensedSign {
        let kind = string(fromCChars: g.kind)
        let text = string(fromCChars: g.text)
        let c = g.corners_raw_px
        return SensedSign(kind: kind, rangeMeters: g.range_m, bearingRad: g.bearing_rad, score: g.score,
                          centerHeightAboveCameraMeters: g.center_height_above_camera_m,
                          cornersRaw: [PixelPoint(u: c.0, v: c.1), PixelPoint(u: c.2, v: c.3),
                                       PixelPoint(u: c.4, v: c.5), PixelPoint(u: c.6, v: c.7)],
                          text: text.isEmpty ? nil : text)
    }

    static var libraryVersion: String { String(cString: wf_sign_detector_version()) }

    static func readImage(path: String, pixelFormat: PixelFormat) throws -> ImageBuffer {
        guard pixelFormat != .nv12 else {
            throw SignDetectorError.invalidArgument("ImageBuffer.load: pixel format must be gray8, rgb8 or bgra8")
        }
        var owned = wf_owned_image()
        let status = wf_image_read(&owned, path, format(pixelFormat))
        guard status == WF_STATUS_OK else { throw error(status: status, message: String(cString: wf_thread_last_error())) }
        defer { wf_owned_image_free(&owned) }
        let bytes = Array(UnsafeBufferPointer(start: owned.data, count: owned.stride * Int(owned.height)))
        return ImageBuffer(width: Int(owned.width), height: Int(owned.height), bytesPerRow: owned.stride,
                           pixelFormat: pixelFormat, data: bytes)
    }

    private static func format(_ f: PixelFormat) -> wf_pixel_format {
        switch f {
        case .gray8: return WF_PIXEL_GRAY8
        case .bgra8: return WF_PIXEL_BGRA8
        case .rgb8: return WF_PIXEL_RGB8
        case .nv12: return WF_PIXEL_NV12
        }
    }

    /// The NUL-terminated UTF-8 string in a fixed C char array (a tuple in Swift), e.g. `wf_sign_sighting.kind`.
    private static func string<Chars>(fromCChars chars: Chars) -> String {
        withUnsafeBytes(of: chars) { raw in String(decoding: raw.prefix { $0 != 0 }, as: UTF8.self) }
    }

    private static func detection(_ o: wf_detector_observation) -> SignDetection {
        let kind = string(fromCChars: o.kind)
        let m = o.unrolled_to_raw
        return SignDetection(
            kind: kind, kindIndex: Int(o.kind_index), score: o.score,
            boxInUnrolled: (o.box_x, o.box_y, o.box_width, o.box_height),
            medianBottomRowPx: o.median_bottom_row_px, medianHeightPx: o.median_height_px,
            centerColumnPx: o.center_column_px, extentWidthPx: o.extent_width_px,
            bottomEdgeSlope: o.bottom_edge_slope, topEdgeSlope: o.top_edge_slope,
            unrolledFx: o.unrolled_fx, unrolledFy: o.unrolled_fy, unrolledCx: o.unrolled_cx, unrolledCy: o.unrolled_cy,
            unrolledWidth: Int(o.unrolled_width), unrolledHeight: Int(o.unrolled_height),
            sliceCount: Int(o.slice_count), appliedRollRad: o.applied_roll_rad,
            unrolledToRaw: [m.0, m.1, m.2, m.3, m.4, m.5])
    }

    static func error(status: Int32, message: String) -> SignDetectorError {
        switch status {
        case WF_STATUS_INVALID_ARGUMENT: return .invalidArgument(message)
        case WF_STATUS_INVALID_CATALOGUE: return .invalidCatalogue(message)
        case WF_STATUS_MODEL_LOAD: return .modelLoad(message)
        case WF_STATUS_BAD_FRAME: return .badFrame(message)
        case WF_STATUS_IMAGE_READ: return .imageRead(message)
        default: return .internalFailure(message.isEmpty ? "status \(status)" : message)
        }
    }
}
