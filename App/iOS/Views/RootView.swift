#if canImport(SwiftUI) && canImport(ARKit) && os(iOS)
import Maps
import SwiftUI
import WayfinderCore

/// The flow: building -> start -> destination -> guidance. VoiceOver first: every control has a label and
/// hint, text uses Dynamic Type styles, and no information is shown only visually.
struct RootView: View {
    @EnvironmentObject var model: AppModel

    var body: some View {
        NavigationStack {
            switch model.state {
            case .choosingBuilding: BuildingPickerView()
            case .choosingStart: StartPickerView()
            case .choosingDestination: DestinationPickerView()
            case .ready, .guiding, .arrived: GuidanceView()
            }
        }
    }
}
#endif
