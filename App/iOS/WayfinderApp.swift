#if canImport(SwiftUI) && os(iOS)
import SwiftUI

/// The app's entry point: one navigation stack over the flow of `GuidanceSession`.
@main
struct WayfinderApp: App {
    @StateObject private var model = AppModel()

    var body: some Scene {
        WindowGroup {
            RootView().environmentObject(model)
        }
    }
}
#endif
