#if canImport(SwiftUI) && canImport(ARKit) && os(iOS)
import Maps
import SwiftUI
import WayfinderCore

/// The flow: first-run onboarding, then building -> start -> destination -> guidance, with Settings in the
/// toolbar. VoiceOver first: every control has a label and hint, text uses Dynamic Type styles, every
/// screen scrolls (List, Form or ScrollView) at the largest accessibility sizes, and Magic Tap (two-finger
/// double tap anywhere) repeats the last instruction or stops speech (`EyesFreeCommandMap`).
struct RootView: View {
    @EnvironmentObject var model: AppModel
    @State private var showingSettings = false

    var body: some View {
        Group {
            if !model.settings.onboardingCompleted {
                OnboardingView()
            } else {
                NavigationStack {
                    flow
                        .toolbar {
                            ToolbarItem(placement: .primaryAction) {
                                Button("Settings") { showingSettings = true }
                                    .accessibilityHint("Units, directions, speech, lanyard mode and recording")
                            }
                        }
                }
            }
        }
        .sheet(isPresented: $showingSettings) { SettingsView() }
        .accessibilityAction(.magicTap) { model.handle(.magicTap) }
    }

    @ViewBuilder private var flow: some View {
        switch model.state {
        case .choosingBuilding: BuildingPickerView()
        case .choosingStart: StartPickerView()
        case .choosingDestination: DestinationPickerView()
        case .ready, .guiding, .arrived: GuidanceView()
        }
    }
}
#endif
