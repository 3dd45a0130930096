#if canImport(SwiftUI) && canImport(ARKit) && os(iOS)
import SwiftUI
import WayfinderCore

/// Start / Stop guidance and the two big request buttons. Works with the phone in hand or on a lanyard:
/// nothing needs to be looked at (Magic Tap repeats, headphone buttons repeat / say where you are); the
/// status line is also announced. Scrolls at the largest text sizes.
struct GuidanceView: View {
    @EnvironmentObject var model: AppModel
    @State private var markingSpot = false
    @State private var spotQuery = ""

    var body: some View {
        ScrollView {
            VStack(spacing: 20) {
                Text(model.statusText)
                    .font(.title2)
                    .frame(maxWidth: .infinity, alignment: .leading)
                    .accessibilityAddTraits(.updatesFrequently)
                if model.offerSettingsLink {
                    Button("Open Settings to allow the camera") { model.openSettingsApp() }
                        .buttonStyle(.borderedProminent)
                }
                if model.guiding {
                    Button("Stop guidance") { model.stopGuidance() }
                        .buttonStyle(.borderedProminent)
                } else {
                    Button("Start guidance") { model.startGuidance() }
                        .buttonStyle(.borderedProminent)
                        .accessibilityHint(model.settings.carry == .lanyard
                                           ? "Check the phone hangs flat on your chest, camera forward, and start walking"
                                           : "Hold the phone camera forward and start walking")
                    Toggle("Record this walk", isOn: $model.settings.recordWalks)
                        .accessibilityHint("Saves this walk on the phone so a trainer can review it")
                }
                Button(action: model.whereAmI) { Text("Where am I?").font(.largeTitle).frame(maxWidth: .infinity, minHeight: 120) }
                    .buttonStyle(.bordered)
                    .accessibilityHint("Also: double-click the headphone button")
                Button(action: model.repeatLast) { Text("Repeat").font(.largeTitle).frame(maxWidth: .infinity, minHeight: 120) }
                    .buttonStyle(.bordered)
                    .accessibilityHint("Also: two-finger double tap anywhere, or one click of the headphone button")
                if model.recordingWalk {
                    Button("Mark where I stand") { markingSpot = true }
                        .buttonStyle(.bordered)
                        .accessibilityHint("For testing: choose the place you are standing at, so the recording can be scored")
                }
                if let url = model.lastBundleURL {
                    ShareLink(item: url) { Text("Share the last recorded walk") }
                }
            }
            .padding()
        }
        .navigationTitle("Guidance")
        .sheet(isPresented: $markingSpot) {
            NavigationStack {
                List(model.snapshot.places?.search(spotQuery) ?? []) { place in
                    Button(place.name) { model.markSurveyedSpot(place.id); markingSpot = false }
                        .accessibilityLabel(place.accessibilityLabel)
                }
                .searchable(text: $spotQuery, prompt: "Search places")
                .navigationTitle("Where do you stand?")
            }
        }
    }
}
#endif
