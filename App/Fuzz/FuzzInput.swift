import Foundation

/// One fuzz input: one or more named files (a map file alone, or the files of a session bundle or an
/// iNavigate folder). Names are relative paths using "/"; files are kept sorted by name.
struct FuzzInput: Equatable, Sendable {
    /// One file of the input.
    struct File: Equatable, Sendable {
        /// Relative path, e.g. "frames.jsonl".
        var name: String
        /// Contents.
        var bytes: [UInt8]
    }

    /// The files, sorted by name.
    var files: [File]

    /// Total size, bytes.
    var byteCount: Int { files.reduce(0) { $0 + $1.bytes.count } }

    /// Contents of the file `name`, if present.
    func bytes(of name: String) -> [UInt8]? { files.first { $0.name == name }?.bytes }

    /// Reads a corpus entry or a reproducer: a regular file is a one-file input named by its last path
    /// component; a directory is every regular file below it (hidden files skipped).
    static func load(from url: URL) throws -> FuzzInput {
        var isDir: ObjCBool = false
        guard FileManager.default.fileExists(atPath: url.path, isDirectory: &isDir) else {
            throw FuzzError("\(url.path): no such file or directory")
        }
        if !isDir.boolValue {
            return FuzzInput(files: [File(name: url.lastPathComponent, bytes: try readBytes(url))])
        }
        var files: [File] = []
        let base = url.standardizedFileURL.path
        guard let e = FileManager.default.enumerator(atPath: base) else { throw FuzzError("\(url.path): cannot list") }
        while let rel = e.nextObject() as? String {
            let full = URL(fileURLWithPath: base).appendingPathComponent(rel)
            var sub: ObjCBool = false
            guard !rel.split(separator: "/").contains(where: { $0.hasPrefix(".") }),
                  FileManager.default.fileExists(atPath: full.path, isDirectory: &sub), !sub.boolValue else { continue }
            files.append(File(name: rel, bytes: try readBytes(full)))
        }
        guard !files.isEmpty else { throw FuzzError("\(url.path): empty directory") }
        return FuzzInput(files: files.sorted { $0.name < $1.name })
    }

    /// Writes the files under `directory` (created if needed) so that it holds exactly this input: files
    /// of an earlier input not in this one are removed. Plain `write(2)` without fsync (the harness rewrites
    /// a scratch directory for every input; Foundation's atomic writes would fsync each file).
    func write(to directory: URL) throws {
        let fm = FileManager.default
        try fm.createDirectory(at: directory, withIntermediateDirectories: true)
        let keep = Set(files.map { String($0.name.split(separator: "/").first ?? "") })
        for name in (try? fm.contentsOfDirectory(atPath: directory.path)) ?? [] where !keep.contains(name) {
            try fm.removeItem(at: directory.appendingPathComponent(name))
        }
        for f in files {
            let url = directory.appendingPathComponent(f.name)
            if f.name.contains("/") {
                try fm.createDirectory(at: url.deletingLastPathComponent(), withIntermediateDirectories: true)
            }
            let fd = open(url.path, O_WRONLY | O_CREAT | O_TRUNC, 0o644)
            guard fd >= 0 else { throw FuzzError("\(url.path): cannot write") }
            defer { close(fd) }
            var done = 0
            while done < f.bytes.count {
                let n = f.bytes.withUnsafeBytes { Glibc.write(fd, $0.baseAddress! + done, f.bytes.count - done) }
                guard n > 0 else { throw FuzzError("\(url.path): write failed") }
                done += n
            }
        }
    }

    private static func readBytes(_ url: URL) throws -> [UInt8] {
        guard let d = FileManager.default.contents(atPath: url.path) else { throw FuzzError("\(url.path): cannot read") }
        return [UInt8](d)
    }
}

/// A usage or set-up error of the fuzz harness itself (bad arguments, unreadable corpus).
struct FuzzError: Error, CustomStringConvertible {
    /// What is wrong.
    var description: String
    init(_ d: String) { description = d }
}
