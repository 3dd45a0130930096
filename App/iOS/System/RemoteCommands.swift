#if canImport(MediaPlayer) && os(iOS)
import MediaPlayer
import WayfinderCore

/// Headphone and lock-screen buttons (MPRemoteCommandCenter, as Soundscape's RemoteCommandManager):
/// each command becomes an `EyesFreeInput`; what it does is decided by the shared `EyesFreeCommandMap`.
/// iOS delivers these only to the Now Playing app, so a Now Playing entry names the walk while guiding
/// (docs/ios.md's checklist verifies the buttons on a device).
@MainActor
final class RemoteCommands {
    private var targets: [(MPRemoteCommand, Any)] = []
    /// Called with each input.
    var onInput: ((EyesFreeInput) -> Void)?

    func enable(title: String) {
        guard targets.isEmpty else { return }
        let center = MPRemoteCommandCenter.shared()
        let map: [(MPRemoteCommand, EyesFreeInput)] = [
            (center.togglePlayPauseCommand, .remoteTogglePlayPause), (center.playCommand, .remotePlay),
            (center.pauseCommand, .remotePause), (center.nextTrackCommand, .remoteNextTrack),
            (center.previousTrackCommand, .remotePreviousTrack),
        ]
        for (command, input) in map {
            command.isEnabled = true
            let target = command.addTarget { [weak self] _ in
                MainActor.assumeIsolated { self?.onInput?(input) }
                return .success
            }
            targets.append((command, target))
        }
        MPNowPlayingInfoCenter.default().nowPlayingInfo = [MPMediaItemPropertyTitle: title]
    }

    func disable() {
        for (command, target) in targets {
            command.removeTarget(target)
            command.isEnabled = false
        }
        targets.removeAll()
        MPNowPlayingInfoCenter.default().nowPlayingInfo = nil
    }
}
#endif
