import Foundation

/// Renders an HTML file to PNG with headless Chromium (Debian's `chromium`, installed by scripts/setup.sh).
public enum ChromiumScreenshot {
    /// Errors of the screenshot step.
    public enum Failure: Error, CustomStringConvertible {
        /// No chromium executable on PATH.
        case chromiumMissing
        /// Chromium ran but wrote no PNG.
        case failed(String)
        /// Message for people.
        public var description: String {
            switch self {
            case .chromiumMissing: return "chromium not found on PATH (run scripts/setup.sh)"
            case .failed(let m): return "chromium screenshot failed: \(m)"
            }
        }
    }

    /// Path of the chromium executable, if installed.
    public static func executable() -> String? {
        let path = ProcessInfo.processInfo.environment["PATH"] ?? "/usr/bin:/bin"
        for dir in path.split(separator: ":") {
            for name in ["chromium", "chromium-browser", "google-chrome"] {
                let p = "\(dir)/\(name)"
                if FileManager.default.isExecutableFile(atPath: p) { return p }
            }
        }
        return nil
    }

    /// Screenshots `html` into `png` at `width` x `height` CSS pixels.
    public static func capture(html: URL, png: URL, width: Int = 1400, height: Int = 1100) throws {
        guard let exe = executable() else { throw Failure.chromiumMissing }
        let p = Process()
        p.executableURL = URL(fileURLWithPath: exe)
        let profile = FileManager.default.temporaryDirectory.appendingPathComponent("wf-chromium-\(getpid())")
        p.arguments = ["--headless", "--disable-gpu", "--no-sandbox", "--hide-scrollbars", "--disable-dev-shm-usage",
                       "--user-data-dir=\(profile.path)", "--screenshot=\(png.path)", "--window-size=\(width),\(height)",
                       html.absoluteURL.absoluteString]
        let pipe = Pipe()
        p.standardOutput = pipe
        p.standardError = pipe
        try? FileManager.default.removeItem(at: png)
        try p.run()
        let output = pipe.fileHandleForReading.readDataToEndOfFile()
        p.waitUntilExit()
        try? FileManager.default.removeItem(at: profile)
        guard FileManager.default.fileExists(atPath: png.path) else {
            throw Failure.failed(String(decoding: output.suffix(600), as: UTF8.self))
        }
    }

    /// The page's DOM after its scripts ran (`chromium --headless --dump-dom`), for tests of the page's
    /// behaviour; `fragment` (without `#`, e.g. "t=12.5") is appended to the file URL. With
    /// `virtualTimeBudgetMilliseconds` Chromium lets the page run that much (virtual) time before the dump
    /// (timers and animation frames, e.g. for Play).
    public static func dumpDOM(html: URL, fragment: String? = nil, virtualTimeBudgetMilliseconds: Int? = nil,
                               timeoutSeconds: Double = 60) throws -> String {
        guard let exe = executable() else { throw Failure.chromiumMissing }
        let p = Process()
        p.executableURL = URL(fileURLWithPath: exe)
        let profile = FileManager.default.temporaryDirectory.appendingPathComponent("wf-chromium-dom-\(getpid())-\(UUID().uuidString)")
        var url = html.absoluteURL.absoluteString
        if let fragment { url += "#" + fragment }
        p.arguments = ["--headless", "--disable-gpu", "--no-sandbox", "--disable-dev-shm-usage",
                       "--user-data-dir=\(profile.path)"]
            + (virtualTimeBudgetMilliseconds.map { ["--virtual-time-budget=\($0)"] } ?? []) + ["--dump-dom", url]
        let scratch = FileManager.default.temporaryDirectory.appendingPathComponent("wf-chromium-dom-\(UUID().uuidString).html")
        _ = FileManager.default.createFile(atPath: scratch.path, contents: nil)
        defer { try? FileManager.default.removeItem(at: scratch); try? FileManager.default.removeItem(at: profile) }
        let handle = try FileHandle(forWritingTo: scratch)
        p.standardOutput = handle
        p.standardError = FileHandle.nullDevice
        try p.run()
        let pid = p.processIdentifier
        let killer = DispatchWorkItem { kill(pid, SIGKILL) }
        DispatchQueue.global().asyncAfter(deadline: .now() + timeoutSeconds, execute: killer)
        p.waitUntilExit()
        killer.cancel()
        try handle.close()
        let dom = String(decoding: try Data(contentsOf: scratch), as: UTF8.self)
        guard p.terminationReason == .exit, !dom.isEmpty else {
            throw Failure.failed("--dump-dom of \(url) ended with status \(p.terminationStatus) and \(dom.count) characters")
        }
        return dom
    }

    /// Width and height of a PNG file from its IHDR chunk; nil when it is not a PNG.
    public static func pngSize(_ url: URL) -> (width: Int, height: Int)? {
        guard let d = try? Data(contentsOf: url), d.count > 24,
              Array(d.prefix(8)) == [0x89, 0x50, 0x4E, 0x47, 0x0D, 0x0A, 0x1A, 0x0A] else { return nil }
        func be32(_ o: Int) -> Int { d[d.startIndex + o ..< d.startIndex + o + 4].reduce(0) { $0 << 8 | Int($1) } }
        return (be32(16), be32(20))
    }
}
