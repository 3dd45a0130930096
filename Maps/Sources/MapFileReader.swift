import Foundation
#if canImport(Glibc)
import Glibc
#elseif canImport(Darwin)
import Darwin
#endif

/// Reads a whole input file for `MapLoader` with POSIX calls, so that every failure has its real reason:
/// a missing file, a symbolic-link loop, a permission problem, something that is not a regular file (FIFO,
/// device, socket, directory) or a file over the size limit. Foundation's `Data(contentsOf:)` reports most
/// of these as "You don't have permission" and blocks on a FIFO or reads `/dev/zero` until memory runs out.
///
/// The file is opened non-blocking (opening a FIFO then returns at once) and checked with `fstat` on the
/// open descriptor, so the check and the read see the same file.
enum MapFileReader {
    /// Why a file could not be read, in words for the user (the caller adds the file name).
    struct Failure: Error { let reason: String }

    /// The bytes of the regular file at `path`, at most `limitBytes` of them.
    /// - Throws: `Failure`.
    static func read(path: String, limitBytes: Int) throws -> Data {
        let fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC)
        if fd < 0 { throw Failure(reason: openFailure(errno: errno, path: path)) }
        defer { close(fd) }
        var st = stat()
        guard fstat(fd, &st) == 0 else { throw Failure(reason: "cannot read the file: \(describe(errno))") }
        let type = st.st_mode & S_IFMT
        guard type == S_IFREG else {
            throw Failure(reason: "not a regular file (it is \(kindName(type))); a map must be a regular JSON file")
        }
        if st.st_size > limitBytes {
            throw Failure(reason: "the file is \(st.st_size) bytes; map files are limited to \(limitBytes) bytes (\(limitBytes >> 20) MiB)")
        }
        // Back to blocking reads for a regular file (O_NONBLOCK has no effect on them, cleared for clarity).
        _ = fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) & ~O_NONBLOCK)
        var out = Data()
        out.reserveCapacity(Int(st.st_size))
        var buffer = [UInt8](repeating: 0, count: 1 << 16)
        while true {
            let n = buffer.withUnsafeMutableBytes { posixRead(fd, $0.baseAddress, $0.count) }
            if n == 0 { break }
            if n < 0 {
                if errno == EINTR { continue }
                throw Failure(reason: "cannot read the file: \(describe(errno))")
            }
            out.append(contentsOf: buffer[0..<n])
            // The file may grow while it is read: the limit holds for what is read, not only for the size.
            if out.count > limitBytes {
                throw Failure(reason: "the file is larger than \(limitBytes) bytes (\(limitBytes >> 20) MiB), the limit for map files")
            }
        }
        return out
    }

    /// `read(2)` under a name that does not clash with this type's `read(path:limitBytes:)`.
    private static func posixRead(_ fd: Int32, _ buffer: UnsafeMutableRawPointer?, _ count: Int) -> Int {
        #if canImport(Glibc)
        return Glibc.read(fd, buffer, count)
        #else
        return Darwin.read(fd, buffer, count)
        #endif
    }

    /// The reason for a failed `open(2)`.
    static func openFailure(errno e: Int32, path: String) -> String {
        switch e {
        case ENOENT:
            // A dangling symbolic link also gives ENOENT: say which it is.
            var st = stat()
            if lstat(path, &st) == 0, st.st_mode & S_IFMT == S_IFLNK {
                return "the file is a symbolic link to a file that does not exist: \(path)"
            }
            return "no such file: \(path)"
        case ELOOP: return "too many levels of symbolic links (a symbolic-link loop): \(path)"
        case EACCES, EPERM: return "permission denied: cannot open \(path) for reading"
        case ENOTDIR: return "a component of the path is not a directory: \(path)"
        case ENAMETOOLONG: return "the path is too long: \(path)"
        default: return "cannot open the file: \(describe(e))"
        }
    }

    /// The C library's words for an errno value, with its symbolic number.
    static func describe(_ e: Int32) -> String { "\(String(cString: strerror(e))) (errno \(e))" }

    /// A file type (st_mode & S_IFMT) in words.
    static func kindName(_ type: mode_t) -> String {
        switch type {
        case S_IFDIR: return "a directory"
        case S_IFIFO: return "a FIFO (named pipe)"
        case S_IFCHR: return "a character device"
        case S_IFBLK: return "a block device"
        case S_IFSOCK: return "a socket"
        case S_IFLNK: return "a symbolic link"
        default: return "not a regular file (mode \(String(type, radix: 8)))"
        }
    }
}
