#if canImport(SwiftUI) && canImport(AVFoundation) && os(iOS)
import AVFoundation
import Navigation
import SwiftUI
import WayfinderCore

/// The traveler's settings (`AppSettings`, persisted in UserDefaults): wording shared with the Linux
/// phrasing options (units, clock-face directions, verbosity), speech rate and voice, lanyard mode,
/// recording, haptics. A Form: scrolls at every text size.
struct SettingsView: View {
    @EnvironmentObject var model: AppModel
    @Environment(\.dismiss) private var dismiss

    private var voices: [AVSpeechSynthesisVoice] {
        let language = model.settings.phrasing.language
        return AVSpeechSynthesisVoice.speechVoices().filter { $0.language.hasPrefix(language) }.sorted { $0.name < $1.name }
    }

    var body: some View {
        NavigationStack {
            Form {
                Section("Directions") {
                    Picker("Distances in", selection: $model.settings.phrasing.distanceUnit) {
                        Text("Meters").tag(DistanceUnit.meters)
                        Text("Feet").tag(DistanceUnit.feet)
                        Text("Steps").tag(DistanceUnit.steps)
                    }
                    Picker("Turns", selection: $model.settings.phrasing.directionStyle) {
                        Text("Turn left, turn right").tag(DirectionStyle.turnWords)
                        Text("With clock directions").tag(DirectionStyle.clockFace)
                    }
                    Picker("How much is said", selection: $model.settings.phrasing.verbosity) {
                        Text("Brief: turns and arrival").tag(Verbosity.brief)
                        Text("Normal").tag(Verbosity.normal)
                        Text("Detailed: also landmarks").tag(Verbosity.detailed)
                    }
                }
                Section("Speech") {
                    Stepper(value: $model.settings.speechRateMultiplier, in: AppSettings.speechRateRange, step: 0.1) {
                        Text("Speech rate \(model.settings.speechRateMultiplier, format: .number.precision(.fractionLength(1))) times")
                    }
                    .accessibilityHint("Used when VoiceOver is off; VoiceOver speaks at its own rate")
                    Picker("Voice", selection: $model.settings.voiceIdentifier) {
                        Text("System voice").tag(String?.none)
                        ForEach(voices, id: \.identifier) { voice in Text(voice.name).tag(Optional(voice.identifier)) }
                    }
                }
                Section("Carrying the phone") {
                    Picker("Carry", selection: $model.settings.carry) {
                        Text("In my hand").tag(PhoneCarry.handheld)
                        Text("On a lanyard").tag(PhoneCarry.lanyard)
                    }
                    .accessibilityHint("Lanyard mode gives the phone's swing more time before saying wrong way")
                    Toggle("Vibrations", isOn: $model.settings.hapticsEnabled)
                    Button("Practice holding the phone again") {
                        model.settings.onboardingCompleted = false
                        dismiss()
                    }
                }
                Section("Recording") {
                    Toggle("Record walks", isOn: $model.settings.recordWalks)
                    Toggle("Include camera pictures", isOn: $model.settings.recordImages)
                        .accessibilityHint("Every tenth picture is saved with the walk so it can be replayed with sign detection")
                }
            }
            .navigationTitle("Settings")
            .toolbar { ToolbarItem(placement: .confirmationAction) { Button("Done") { dismiss() } } }
        }
    }
}
#endif
