#if canImport(SwiftUI) && canImport(ARKit) && os(iOS)
import SwiftUI
import WayfinderCore

/// Start / Stop guidance and the two big request buttons. Works with the phone in hand or on a lanyard:
/// nothing needs to be looked at; the status line is also announced.
struct GuidanceView: View {
    @EnvironmentObject var model: AppModel

    var body: some View {
        VStack(spacing: 20) {
            Text(model.statusText)
                .font(.title2)
                .accessibilityAddTraits(.updatesFrequently)
            if model.state == .guiding {
                Button("Stop guidance") { model.stopGuidance() }
                    .buttonStyle(.borderedProminent)
            } else {
                Button("Start guidance") { model.startGuidance() }
                    .buttonStyle(.borderedProminent)
                    .accessibilityHint("Hold the phone camera forward and start walking")
                Toggle("Record this walk", isOn: $model.recording)
                    .accessibilityHint("Saves this walk on the phone so a trainer can review it")
            }
            Button(action: model.whereAmI) { Text("Where am I?").font(.largeTitle).frame(maxWidth: .infinity, minHeight: 120) }
                .buttonStyle(.bordered)
            Button(action: model.repeatLast) { Text("Repeat").font(.largeTitle).frame(maxWidth: .infinity, minHeight: 120) }
                .buttonStyle(.bordered)
            if let url = model.recorder.lastBundleURL {
                ShareLink(item: url) { Text("Share the last recorded walk") }
            }
        }
        .padding()
        .navigationTitle("Guidance")
    }
}
#endif
