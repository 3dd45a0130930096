import Foundation
#if canImport(Glibc)
import Glibc
#elseif canImport(Darwin)
import Darwin
#endif

/// How the reader opens the files of a bundle (policy in docs/session-format.md, "Links and special files"):
///
/// - Symbolic links are resolved (realpath(3)) and the target must lie inside the bundle directory (itself
///   resolved, so a bundle reached through a link is fine). A link that leaves the bundle is refused
///   (`BundleError.Kind.linkOutsideBundle`), as is a link loop.
/// - The target must be a regular file: FIFOs, devices (`/dev/zero`), sockets and directories are refused
///   (`.notARegularFile`) before a single byte is read. Files are opened with `O_NONBLOCK`, so even a FIFO
///   swapped in after the check cannot block the open, and the type is checked again on the open
///   descriptor (fstat).
/// - Reads are bounded: JSON-lines files line by line (`BundleLineRecord.maximumLineBytes`), session.json
///   as a whole (`maximumSessionFileBytes`).
enum BundleFileAccess {
    /// What a bundle path resolves to.
    enum Target {
        /// A regular file inside the bundle, at this resolved absolute path.
        case regularFile(String)
        /// Nothing there (no file, or a link to nothing).
        case missing
    }

    /// realpath(3) of `path`: the resolved path, or nil and errno.
    static func realPath(_ path: String) -> (path: String?, error: Int32) {
        guard let p = realpath(path, nil) else { return (nil, errno) }
        defer { free(p) }
        return (String(cString: p), 0)
    }

    /// The bundle directory with every link resolved, or its own path when it cannot be resolved (the
    /// caller has already checked that it exists).
    static func resolvedRoot(_ bundle: URL) -> String {
        if let p = realPath(bundle.path).path { return p }
        return bundle.standardizedFileURL.path
    }

    /// True when the resolved `path` is `root` itself or lies below it.
    static func isInside(_ path: String, root: String) -> Bool {
        if root == "/" { return true }
        return path == root || path.hasPrefix(root.hasSuffix("/") ? root : root + "/")
    }

    /// True when `path` itself (not its target) is a symbolic link.
    static func isSymbolicLink(_ path: String) -> Bool {
        var st = stat()
        return lstat(path, &st) == 0 && (st.st_mode & S_IFMT) == S_IFLNK
    }

    /// Words for a file type from `st_mode`.
    static func typeName(_ mode: mode_t) -> String {
        switch mode & S_IFMT {
        case S_IFIFO: return "a FIFO (named pipe)"
        case S_IFCHR: return "a character device"
        case S_IFBLK: return "a block device"
        case S_IFSOCK: return "a socket"
        case S_IFDIR: return "a directory"
        case S_IFLNK: return "a symbolic link"
        default: return "not a regular file"
        }
    }

    /// Resolves `url` under the policy. `root` is the resolved bundle directory.
    /// - Throws: `BundleError` `.linkOutsideBundle` (a link leaving the bundle, or a link loop),
    ///   `.notARegularFile`, `.unreadableFile` (permission or I/O problems while resolving).
    static func resolve(_ url: URL, root: String) throws -> Target {
        let path = url.path
        let (found, e) = realPath(path)
        guard let resolved = found else {
            if e == ENOENT || e == ENOTDIR { return .missing }
            if e == ELOOP {
                throw BundleError(.linkOutsideBundle, file: path,
                                  reason: "symbolic link loop (too many levels of links); links in a bundle must lead to "
                                      + "a file inside it")
            }
            throw BundleError(.unreadableFile, file: path, reason: "cannot resolve the path: \(String(cString: strerror(e)))")
        }
        guard isInside(resolved, root: root) else {
            throw BundleError(.linkOutsideBundle, file: path,
                              reason: "is a symbolic link (or lies under one) to \(resolved), outside the bundle directory "
                                  + "\(root); links that leave the bundle are refused (docs/session-format.md)")
        }
        var st = stat()
        guard stat(resolved, &st) == 0 else {
            if errno == ENOENT { return .missing }
            throw BundleError(.unreadableFile, file: path, reason: "cannot stat: \(String(cString: strerror(errno)))")
        }
        guard (st.st_mode & S_IFMT) == S_IFREG else {
            throw BundleError(.notARegularFile, file: path,
                              reason: "is \(typeName(st.st_mode))\(resolved == path ? "" : " (\(resolved))"), not a regular "
                                  + "file; refused (a bundle holds only regular files)")
        }
        return .regularFile(resolved)
    }

    /// Opens `url` for reading under the policy. Throws `.missingFile` when there is nothing there.
    /// `root` nil: no containment rule (an input file outside any bundle, such as an importer's source),
    /// only the regular-file rule.
    static func openForReading(_ url: URL, root: String?) throws -> ReadOnlyFile {
        let path = url.path
        guard case .regularFile(let resolved) = try resolve(url, root: root ?? "/") else {
            if isSymbolicLink(path) {
                throw BundleError(.missingFile, file: path, reason: "is a symbolic link to a file that does not exist")
            }
            throw BundleError(.missingFile, file: path, reason: "file not found")
        }
        let fd = open(resolved, O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOFOLLOW)
        guard fd >= 0 else {
            let e = errno
            if e == EACCES || e == EPERM {
                throw BundleError(.unreadableFile, file: path, reason: "permission denied")
            }
            throw BundleError(.unreadableFile, file: path, reason: "cannot open: \(String(cString: strerror(e)))")
        }
        var st = stat()
        guard fstat(fd, &st) == 0, (st.st_mode & S_IFMT) == S_IFREG else {
            let mode = st.st_mode
            _ = posixCloseFile(fd)
            throw BundleError(.notARegularFile, file: path,
                              reason: "is \(typeName(mode)), not a regular file; refused (a bundle holds only regular files)")
        }
        return ReadOnlyFile(fd: fd, path: path)
    }
}

/// An open, read-only regular file (closed on deinit).
final class ReadOnlyFile {
    /// Path as opened (for messages).
    let path: String
    private let fd: Int32
    private var isOpen = true

    init(fd: Int32, path: String) { self.fd = fd; self.path = path }
    deinit { close() }

    /// Appends up to `count` bytes to `buffer`; returns the number read (0 at the end of the file).
    func read(into buffer: inout [UInt8], upTo count: Int) throws -> Int {
        let old = buffer.count
        buffer.reserveCapacity(old + count)
        var n = 0
        buffer.append(contentsOf: repeatElement(0, count: count))
        while true {
            n = buffer.withUnsafeMutableBytes { raw in posixRead(fd, raw.baseAddress! + old, count) }
            if n < 0 && errno == EINTR { continue }
            break
        }
        buffer.removeLast(count - max(n, 0))
        if n < 0 { throw POSIXErrorCode(rawValue: errno).map { POSIXError($0) } ?? POSIXError(.EIO) }
        return n
    }

    /// The whole file, refusing files longer than `limit` bytes (`.fileTooLarge`).
    func readAll(limit: Int) throws -> Data {
        var buffer: [UInt8] = []
        while true {
            let n: Int
            do { n = try read(into: &buffer, upTo: 1 << 16) } catch {
                throw BundleError(.unreadableFile, file: path, reason: "read failed: \(error.localizedDescription)")
            }
            if n == 0 { break }
            if buffer.count > limit {
                throw BundleError(.fileTooLarge, file: path,
                                  reason: "larger than the limit of \(limit) bytes for this file; refused")
            }
        }
        return Data(buffer)
    }

    func close() {
        guard isOpen else { return }
        isOpen = false
        _ = posixCloseFile(fd)
    }
}

/// read(2), named apart from `ReadOnlyFile.read`.
@inline(__always) private func posixRead(_ fd: Int32, _ buf: UnsafeMutableRawPointer, _ count: Int) -> Int {
    #if canImport(Glibc)
    return Glibc.read(fd, buf, count)
    #else
    return Darwin.read(fd, buf, count)
    #endif
}

/// close(2), named apart from the classes' own `close()`.
@inline(__always) func posixCloseFile(_ fd: Int32) -> Int32 {
    #if canImport(Glibc)
    return Glibc.close(fd)
    #else
    return Darwin.close(fd)
    #endif
}

/// Largest session.json accepted, bytes (1 MiB; a real one is under 1 KiB).
public let maximumSessionFileBytes = 1 << 20
