#if canImport(SwiftUI) && canImport(CoreMotion) && os(iOS)
import SwiftUI
import WayfinderCore

/// First run (`OnboardingStep`): the safety notice, hand or lanyard, how to hold the phone, then a
/// practice in which `OrientationCoach` speaks pitch / roll corrections from the motion sensors until the
/// phone is held right for 3 s (Clew's phone-orientation training). Every step is spoken and scrolls.
struct OnboardingView: View {
    @EnvironmentObject var model: AppModel
    @State private var step: OnboardingStep = .safety
    @State private var coach: OrientationCoach?
    @State private var lastFeedback = ""
    @State private var attitude = AttitudeSource()

    var body: some View {
        ScrollView {
            VStack(alignment: .leading, spacing: 24) {
                switch step {
                case .safety:
                    Text("Before you start").font(.largeTitle).accessibilityAddTraits(.isHeader)
                    Text(step.text(model.phrases, carry: model.settings.carry) ?? "").font(.title3)
                    Button("I understand") { advance() }.buttonStyle(.borderedProminent)
                case .carry:
                    Text("How will you carry the phone?").font(.largeTitle).accessibilityAddTraits(.isHeader)
                    Button("In my hand") { model.settings.carry = .handheld; advance() }.buttonStyle(.borderedProminent)
                    Button("On a lanyard") { model.settings.carry = .lanyard; advance() }.buttonStyle(.bordered)
                case .hold:
                    Text("Holding the phone").font(.largeTitle).accessibilityAddTraits(.isHeader)
                    Text(step.text(model.phrases, carry: model.settings.carry) ?? "").font(.title3)
                    Button("Practice now") { advance() }.buttonStyle(.borderedProminent)
                case .practice:
                    Text("Practice").font(.largeTitle).accessibilityAddTraits(.isHeader)
                    Text(lastFeedback).font(.title3).accessibilityAddTraits(.updatesFrequently)
                    if coach?.completed == true {
                        Button("Start using Wayfinder") { finish() }.buttonStyle(.borderedProminent)
                    }
                    Button("Skip the practice") { finish() }.buttonStyle(.bordered)
                }
            }
            .padding()
            .frame(maxWidth: .infinity, alignment: .leading)
        }
        .onAppear { say(step) }
        .onDisappear { attitude.stop() }
    }

    private func advance() {
        guard let next = step.next else { return finish() }
        step = next
        say(next)
        if next == .practice { startPractice() }
    }

    private func say(_ s: OnboardingStep) {
        if let text = s.text(model.phrases, carry: model.settings.carry) { model.speech.speak(text, interrupt: true, requested: true) }
    }

    private func startPractice() {
        coach = OrientationCoach(profile: model.settings.carryProfile, phrases: model.phrases)
        attitude.onAttitude = { a, t in
            guard var c = coach else { return }
            let spoken = c.update(a, t: t)
            coach = c
            guard let text = spoken else { return }
            lastFeedback = text
            model.speech.speak(text, interrupt: true, requested: true)
        }
        attitude.start()
    }

    private func finish() {
        attitude.stop()
        model.settings.onboardingCompleted = true
    }
}
#endif
