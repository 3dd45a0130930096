import XCTest
import Navigation
import SessionFormat
@testable import WayfinderCore

/// The iPhone shell's logic (App/Core/Phone), tested on Linux: settings, session health, the speech
/// queue, the haptic vocabulary, eyes-free commands, screen wake and the orientation coach.
final class PhoneShellTests: XCTestCase {
    static let phrases: PhonePhrases = try! PhonePhrases.load(language: "en")
    var phrases: PhonePhrases { Self.phrases }

    // MARK: phrases

    func testEveryPhoneKeyIsInTheEnglishPhraseBook() throws {
        XCTAssertEqual(phrases.missingKeys, [], "add these keys to Navigation/Locales/en.json")
        for key in PhoneKey.allCases { XCTAssertNotEqual(phrases.text(key), key.rawValue) }
    }

    func testMissingKeyFallsBackToEnglish() throws {
        let json = try Data(contentsOf: TestData.packageRoot.appendingPathComponent("Navigation/Locales/en.json"))
        var file = try JSONSerialization.jsonObject(with: json) as! [String: Any]
        var table = file["phrases"] as! [String: String]
        table["phone.paused"] = nil
        table["phone.resumed"] = "Seguimos."
        file["phrases"] = table
        let book = try PhraseBook(language: "xx", json: JSONSerialization.data(withJSONObject: file), sourceName: "xx.json")
        let p = PhonePhrases(book: book, fallback: try PhraseBook.load(language: "en"))
        XCTAssertEqual(p.missingKeys, [.paused])
        XCTAssertEqual(p.text(.resumed), "Seguimos.")
        XCTAssertEqual(p.text(.paused), phrases.text(.paused))
    }

    // MARK: settings

    func testSettingsRoundTripAndLenientDecoding() throws {
        var s = AppSettings()
        s.phrasing = PhrasingOptions(distanceUnit: .feet, directionStyle: .clockFace, verbosity: .brief)
        s.speechRateMultiplier = 1.4
        s.voiceIdentifier = "com.apple.voice.compact.en-GB.Daniel"
        s.carry = .lanyard
        s.recordWalks = true
        XCTAssertEqual(AppSettings.decode(s.encoded()).settings, s)
        XCTAssertNil(AppSettings.decode(s.encoded()).warning)
        // First run.
        XCTAssertEqual(AppSettings.decode(nil).settings, AppSettings())
        // An older version without most fields, and out-of-range values.
        let old = Data(#"{"carry": "lanyard", "speechRateMultiplier": 9, "recordImageEveryNthFrame": 0, "phrasing": 3}"#.utf8)
        let (o, warning) = AppSettings.decode(old)
        XCTAssertNil(warning)
        XCTAssertEqual(o.carry, .lanyard)
        XCTAssertEqual(o.speechRateMultiplier, 2.0)
        XCTAssertEqual(o.recordImageEveryNthFrame, 1)
        XCTAssertEqual(o.phrasing, PhrasingOptions(), "an undecodable field takes its default")
        // Not JSON: defaults and a warning that names the key.
        let bad = AppSettings.decode(Data("not json".utf8))
        XCTAssertEqual(bad.settings, AppSettings())
        XCTAssertTrue(bad.warning?.contains(AppSettings.userDefaultsKey) ?? false)
    }

    func testLanyardModeChangesThePipelineAndTheCoach() {
        var s = AppSettings()
        let handheld = s.pipelineOptions()
        s.carry = .lanyard
        s.phrasing.language = "es"
        let lanyard = s.pipelineOptions()
        XCTAssertEqual(handheld.navigator.wrongWaySustainSeconds, 2.0)
        XCTAssertEqual(lanyard.navigator.wrongWaySustainSeconds, 3.0)
        XCTAssertEqual(lanyard.navigator.language, "es")
        XCTAssertGreaterThan(CarryProfile.of(.lanyard).pitchToleranceDeg, CarryProfile.of(.handheld).pitchToleranceDeg)
        XCTAssertEqual(SpeechRate.synthesizerRate(multiplier: 1), 0.5)
        XCTAssertEqual(SpeechRate.synthesizerRate(multiplier: 1.5), 0.75)
        XCTAssertEqual(SpeechRate.synthesizerRate(multiplier: 5), 1.0)
    }

    // MARK: session health

    private func speech(_ commands: [HealthCommand]) -> [String] {
        commands.compactMap { if case .speak(let t, _) = $0 { return t } else { return nil } }
    }

    func testPermissionIsCheckedBeforeGuidanceAndADenialIsSpoken() {
        var h = SessionHealth(phrases: phrases)
        XCTAssertEqual(h.handle(.startRequested(.authorized)), [.beginGuidance])
        XCTAssertEqual(h.handle(.stopped), [])

        XCTAssertEqual(h.handle(.startRequested(.notDetermined)), [.requestCameraPermission])
        let denied = h.handle(.permissionAnswered(granted: false))
        XCTAssertEqual(speech(denied), [phrases.text(.cameraDenied)])
        XCTAssertTrue(denied.contains(.offerSettings(true)))
        XCTAssertEqual(h.statusOverride, phrases.text(.statusCameraDenied))
        XCTAssertFalse(denied.contains(.beginGuidance))

        // Denied earlier (Settings): spoken at once; restricted: no Settings button (it would not help).
        var h2 = SessionHealth(phrases: phrases)
        XCTAssertEqual(speech(h2.handle(.startRequested(.denied))), [phrases.text(.cameraDenied)])
        var h3 = SessionHealth(phrases: phrases)
        let restricted = h3.handle(.startRequested(.restricted))
        XCTAssertEqual(speech(restricted), [phrases.text(.cameraRestricted)])
        XCTAssertTrue(restricted.contains(.offerSettings(false)))
        // Allowed later: the override goes away and guidance begins.
        XCTAssertEqual(h3.handle(.startRequested(.authorized)), [.status(nil), .offerSettings(false), .beginGuidance])
    }

    func testFailureInterruptionAndStallAreNeverSilent() {
        var h = SessionHealth(phrases: phrases)
        _ = h.handle(.startRequested(.authorized))
        _ = h.handle(.sessionStarted(t: 0))
        for i in 0..<30 { XCTAssertEqual(h.handle(.frame(t: Double(i) / 30, tracking: .normal, reason: nil)), []) }
        XCTAssertEqual(h.handle(.tick(t: 1.5)), [], "frames are fresh")

        // Interrupted: spoken and shown at once; frames resume after it ends: spoken again.
        let cut = h.handle(.interrupted(t: 2))
        XCTAssertEqual(speech(cut), [phrases.text(.sessionInterrupted)])
        XCTAssertEqual(h.statusOverride, phrases.text(.statusInterrupted))
        XCTAssertEqual(h.handle(.tick(t: 10)), [], "already told")
        XCTAssertEqual(h.handle(.interruptionEnded(t: 20)), [])
        let back = h.handle(.frame(t: 20.1, tracking: .limited, reason: .relocalizing))
        XCTAssertEqual(speech(back), [phrases.text(.sessionResumed)])
        XCTAssertNil(h.statusOverride)

        // No frames for 2 s: a stall, said once; the next frame resumes.
        XCTAssertEqual(h.handle(.tick(t: 21)), [])
        let stall = h.handle(.tick(t: 22.2))
        XCTAssertEqual(speech(stall), [phrases.text(.sessionNoFrames)])
        XCTAssertEqual(h.handle(.tick(t: 23.2)), [])
        XCTAssertEqual(speech(h.handle(.frame(t: 23.5, tracking: .normal, reason: nil))), [phrases.text(.sessionResumed)])

        // An interruption that ends with no frames afterwards is a stall, spoken.
        _ = h.handle(.interrupted(t: 30))
        _ = h.handle(.interruptionEnded(t: 31))
        XCTAssertEqual(speech(h.handle(.tick(t: 33.5))), [phrases.text(.sessionNoFrames)])

        // A failed session ends guidance with the reason.
        let failed = h.handle(.sessionFailed(.sensorFailed))
        XCTAssertEqual(failed.first, .endGuidance)
        XCTAssertEqual(speech(failed), [phrases.text(.sessionFailed)])
        XCTAssertEqual(h.state, .failed)
        XCTAssertEqual(h.handle(.frame(t: 40, tracking: .normal, reason: nil)), [], "a failed session says nothing more")
        // The shell stops the sensors on .endGuidance: the reason stays on the status line until Start.
        XCTAssertEqual(h.handle(.stopped), [])
        XCTAssertEqual(h.statusOverride, phrases.text(.statusFailed))
        XCTAssertEqual(h.handle(.startRequested(.authorized)), [.status(nil), .offerSettings(false), .beginGuidance])
    }

    func testStuckTrackingIsSpokenAndRepeatedWhileTheStatusSaysSo() {
        var h = SessionHealth(phrases: phrases, carry: .lanyard)
        _ = h.handle(.startRequested(.authorized))
        var spoken: [(Double, String)] = []
        // 30 s of "initializing" at 10 Hz (TrackingPromptPolicy says nothing for it).
        for i in 0..<300 {
            let t = Double(i) / 10
            for s in speech(h.handle(.frame(t: t, tracking: .limited, reason: .initializing))) { spoken.append((t, s)) }
        }
        XCTAssertEqual(spoken.map(\.1), Array(repeating: phrases.text(.trackingStuckLanyard), count: 2))
        XCTAssertEqual(spoken[0].0, 8, accuracy: 0.05)
        XCTAssertEqual(spoken[1].0, 23, accuracy: 0.05)
        XCTAssertEqual(h.statusOverride, phrases.text(.statusTracking))
        // Normal tracking clears the status; a brief relocalization stays silent.
        XCTAssertEqual(h.handle(.frame(t: 30, tracking: .normal, reason: nil)), [.status(nil)])
        for i in 0..<50 { XCTAssertEqual(speech(h.handle(.frame(t: 30.1 + Double(i) / 10, tracking: .limited, reason: .relocalizing))), []) }
        // Critical heat is said once.
        XCTAssertEqual(speech(h.handle(.thermal(.critical))), [phrases.text(.thermalCritical)])
        XCTAssertEqual(h.handle(.thermal(.critical)), [])
    }

    /// Relocalizing that lasts restarts world tracking once per spell (ARKit may otherwise relocalize forever);
    /// a brief relocalization does not, and the restart is not spoken (the stuck-tracking prompt covers it).
    func testLongRelocalizingRestartsTrackingOncePerSpell() {
        var h = SessionHealth(phrases: phrases)
        _ = h.handle(.startRequested(.authorized))
        _ = h.handle(.frame(t: 0, tracking: .normal, reason: nil))
        func restarts(from t0: Double, seconds: Double) -> [Double] {
            var at: [Double] = []
            for i in 0..<Int(seconds * 10) {
                let t = t0 + Double(i) / 10
                if h.handle(.frame(t: t, tracking: .limited, reason: .relocalizing)).contains(.restartTracking) { at.append(t) }
            }
            return at
        }
        let first = restarts(from: 1, seconds: 20)
        XCTAssertEqual(first.count, 1)
        XCTAssertEqual(first.first ?? -1, 7, accuracy: 0.05)
        // Tracking back (the restart's initializing, then normal): the next long spell restarts again.
        _ = h.handle(.frame(t: 21, tracking: .limited, reason: .initializing))
        _ = h.handle(.frame(t: 22, tracking: .normal, reason: nil))
        XCTAssertEqual(restarts(from: 30, seconds: 5.5), [])
        _ = h.handle(.frame(t: 36, tracking: .normal, reason: nil))
        XCTAssertEqual(restarts(from: 40, seconds: 7).count, 1)
        // Excessive motion or too few features are not relocalizing: no restart however long.
        _ = h.handle(.frame(t: 48, tracking: .normal, reason: nil))
        for i in 0..<200 {
            XCTAssertFalse(h.handle(.frame(t: 50 + Double(i) / 10, tracking: .limited, reason: .insufficientFeatures))
                .contains(.restartTracking))
        }
        // Off.
        var off = SessionHealth(phrases: phrases)
        off.relocalizationTimeoutSeconds = 0
        _ = off.handle(.startRequested(.authorized))
        for i in 0..<200 {
            XCTAssertFalse(off.handle(.frame(t: Double(i) / 10, tracking: .limited, reason: .relocalizing)).contains(.restartTracking))
        }
    }

    // MARK: speech queue

    private func queue(voiceOver: Bool) -> SpeechQueue {
        SpeechQueue(voiceOverRunning: voiceOver, synthesizerRate: 0.5, outputLostText: phrases.text(.headphonesGone))
    }

    func testSynthesizerQueueWaitsForCompletionAndReleasesTheAudioSession() {
        var q = queue(voiceOver: false)
        XCTAssertEqual(q.handle(.say("A", interrupt: false, t: 0)),
                       [.activateAudioSession, .synthesize(id: 1, text: "A", rate: 0.5, voiceIdentifier: nil)])
        XCTAssertEqual(q.handle(.say("B", interrupt: false, t: 0.1)), [], "waits for A to finish")
        XCTAssertEqual(q.handle(.synthesizerFinished(id: 99)), [], "another utterance's event")
        XCTAssertEqual(q.handle(.synthesizerFinished(id: 1)), [.synthesize(id: 2, text: "B", rate: 0.5, voiceIdentifier: nil)])
        XCTAssertEqual(q.handle(.synthesizerFinished(id: 2)), [.deactivateAudioSession], "others un-duck when the queue empties")
        XCTAssertFalse(q.audioActive)
        // An interrupting cue cuts the current one and drops the waiting ones.
        _ = q.handle(.say("C", interrupt: false, t: 1))
        _ = q.handle(.say("D", interrupt: false, t: 1))
        XCTAssertEqual(q.handle(.say("Turn left now.", interrupt: true, t: 1.2)),
                       [.stopSpeaking, .synthesize(id: 5, text: "Turn left now.", rate: 0.5, voiceIdentifier: nil)])
        XCTAssertEqual(q.handle(.synthesizerCancelled(id: 3)), [], "the cancelled one's event changes nothing")
        XCTAssertEqual(q.waiting, [])
        XCTAssertEqual(q.handle(.synthesizerFinished(id: 5)), [.deactivateAudioSession])
    }

    func testVoiceOverAnnouncementCutOffIsRetriedOnce() {
        var q = queue(voiceOver: true)
        XCTAssertEqual(q.handle(.say("Turn right now.", interrupt: true, t: 0)), [.activateAudioSession, .announce(id: 1, text: "Turn right now.")])
        XCTAssertEqual(q.handle(.announcementFinished(text: "Turn right now.", success: false)), [.announce(id: 1, text: "Turn right now.")])
        XCTAssertEqual(q.handle(.announcementFinished(text: "Turn right now.", success: false)), [.deactivateAudioSession], "retried once only")
        _ = q.handle(.say("X", interrupt: false, t: 1))
        XCTAssertEqual(q.handle(.announcementFinished(text: "Something VoiceOver said", success: true)), [])
        XCTAssertEqual(q.handle(.announcementFinished(text: "X", success: true)), [.deactivateAudioSession])
    }

    func testALostCompletionDoesNotSilenceTheQueue() {
        var q = queue(voiceOver: true)
        _ = q.handle(.say("Continue 20 meters.", interrupt: false, t: 10))
        _ = q.handle(.say("Then turn left.", interrupt: false, t: 10.5))
        XCTAssertEqual(q.handle(.tick(t: 14)), [], "3 words: allowed 5 s")
        XCTAssertEqual(q.handle(.tick(t: 15.5)), [.announce(id: 2, text: "Then turn left.")], "no notification came: given up")
        XCTAssertEqual(q.handle(.announcementFinished(text: "Then turn left.", success: true)), [.deactivateAudioSession])
    }

    func testInterruptionAndHeadphonesUnplugged() {
        var q = queue(voiceOver: false)
        _ = q.handle(.say("In 8 meters, turn left.", interrupt: false, t: 0))
        XCTAssertEqual(q.handle(.interruptionBegan(t: 1)), [])
        XCTAssertEqual(q.handle(.say("lost while the call rings", interrupt: false, t: 2)),
                       [], "nothing starts during an interruption")
        // Resumed soon: the cut utterance is said again.
        XCTAssertEqual(q.handle(.interruptionEnded(shouldResume: true, t: 4)),
                       [.activateAudioSession, .synthesize(id: 1, text: "In 8 meters, turn left.", rate: 0.5, voiceIdentifier: nil)])
        // Headphones unplugged mid-utterance: say so from the speaker, then repeat it.
        let lost = q.handle(.outputDeviceLost(t: 5))
        XCTAssertEqual(lost.first, .stopSpeaking)
        XCTAssertEqual(lost.last, .synthesize(id: 3, text: phrases.text(.headphonesGone), rate: 0.5, voiceIdentifier: nil))
        XCTAssertEqual(q.handle(.synthesizerFinished(id: 3)), [.synthesize(id: 1, text: "In 8 meters, turn left.", rate: 0.5, voiceIdentifier: nil)])
        // A long interruption: the cut text is stale and not repeated.
        _ = q.handle(.interruptionBegan(t: 6))
        XCTAssertEqual(q.handle(.interruptionEnded(shouldResume: true, t: 60)), [])
    }

    func testPauseDropsGuidanceButAnswersRequests() {
        var q = queue(voiceOver: false)
        _ = q.handle(.say("Continue 20 meters.", interrupt: false, t: 0))
        XCTAssertEqual(q.handle(.pause(t: 1)), [.stopSpeaking, .deactivateAudioSession])
        XCTAssertEqual(q.handle(.say("Turn left now.", interrupt: true, t: 2)), [])
        XCTAssertEqual(q.handle(.say("Near Room 101.", interrupt: true, requested: true, t: 3)).last,
                       .synthesize(id: 2, text: "Near Room 101.", rate: 0.5, voiceIdentifier: nil))
        _ = q.handle(.resume(t: 4))
        XCTAssertFalse(q.handle(.say("Turn right now.", interrupt: true, t: 5)).isEmpty)
    }

    // MARK: haptics

    func testHapticVocabularyHasOneDistinctPatternPerEvent() {
        let all = HapticCue.allCases
        for cue in all {
            let p = cue.pattern
            XCTAssertFalse(p.isEmpty, "\(cue)")
            XCTAssertEqual(p.first?.timeSeconds, 0, "\(cue) starts at once")
            XCTAssertEqual(p.map(\.timeSeconds), p.map(\.timeSeconds).sorted(), "\(cue) in time order")
            for e in p {
                XCTAssertTrue((0...1).contains(e.intensity) && (0...1).contains(e.sharpness), "\(cue)")
                XCTAssertLessThanOrEqual(e.timeSeconds + e.durationSeconds, 1.5, "\(cue) is short")
            }
        }
        // Every pattern differs from every other.
        for (i, a) in all.enumerated() { for b in all[(i + 1)...] { XCTAssertNotEqual(a.pattern, b.pattern, "\(a) vs \(b)") } }
        // Left and right differ in rhythm, not only strength; corrections do not feel like turns.
        XCTAssertEqual(HapticCue.turnLeft.rhythm, "LS")
        XCTAssertEqual(HapticCue.turnRight.rhythm, "SL")
        let turnRhythms = Set([HapticCue.turnLeft, .turnRight, .sharpLeft, .sharpRight, .uTurn].map(\.rhythm))
        XCTAssertEqual(turnRhythms.count, 5)
        for c in [HapticCue.offRoute, .wrongWay, .arrived] {
            XCTAssertFalse(turnRhythms.contains(c.rhythm), "\(c) must not feel like a turn")
        }
        XCTAssertNotEqual(HapticCue.offRoute.pattern.map(\.timeSeconds), HapticCue.wrongWay.pattern.map(\.timeSeconds))
    }

    func testHapticNamesMapExactlyAndTurnSideComesFromTheCuePhrase() throws {
        XCTAssertEqual(HapticCue(patternName: "wrongWay"), .wrongWay)
        XCTAssertEqual(HapticCue(patternName: "offRoute"), .offRoute)
        XCTAssertEqual(HapticCue(patternName: "arrived"), .arrived)
        XCTAssertEqual(HapticCue(patternName: "turnCue"), .turn)
        XCTAssertNil(HapticCue(patternName: "wrongWayish"), "no substring matching")
        XCTAssertNil(HapticCue(patternName: "arriv"))
        let book = try PhraseBook.load(language: "en")
        let r = TurnCueResolver(phrases: book)
        XCTAssertEqual(r.cues(of: [.haptic("turnCue"), .speak(book.phrase("cue.turnLeft"), interrupt: true)]), [.turnLeft])
        XCTAssertEqual(r.cues(of: [.haptic("turnCue"), .speak(book.phrase("cue.sharpRight"), interrupt: true)]), [.sharpRight])
        XCTAssertEqual(r.cues(of: [.haptic("turnCue"), .speak("Continue 5 meters.", interrupt: false)]), [.turn])
        // A clock-face cue ("Turn left now, toward 9 o'clock.") is the same cue.
        XCTAssertEqual(r.cues(of: [.haptic("turnCue"),
                                   .speak(book.phrase("cue.turnLeft", ["toward": ", toward 9 o'clock"]), interrupt: true)]),
                       [.turnLeft])
        XCTAssertEqual(r.cues(of: [.haptic("offRoute"), .speak(book.phrase("safety.offRoute"), interrupt: true)]), [.offRoute])
    }

    // MARK: eyes-free commands, screen wake

    func testEyesFreeCommandMap() {
        typealias M = EyesFreeCommandMap
        XCTAssertEqual(M.action(for: .magicTap, speaking: false, speechPaused: false, guiding: true), .repeatLast)
        XCTAssertEqual(M.action(for: .magicTap, speaking: true, speechPaused: false, guiding: true), .silence)
        XCTAssertEqual(M.action(for: .remoteTogglePlayPause, speaking: false, speechPaused: true, guiding: true), .resumeSpeech)
        XCTAssertEqual(M.action(for: .remotePause, speaking: false, speechPaused: false, guiding: true), .pauseSpeech)
        XCTAssertEqual(M.action(for: .remotePause, speaking: true, speechPaused: false, guiding: false), .silence)
        XCTAssertEqual(M.action(for: .remotePause, speaking: false, speechPaused: false, guiding: false), EyesFreeAction.none)
        XCTAssertEqual(M.action(for: .remoteNextTrack, speaking: true, speechPaused: true, guiding: true), .whereAmI)
        XCTAssertEqual(M.action(for: .remotePreviousTrack, speaking: false, speechPaused: false, guiding: false), .repeatLast)
        XCTAssertEqual(M.action(for: .whereAmIButton, speaking: true, speechPaused: false, guiding: false), .whereAmI)
        XCTAssertEqual(M.action(for: .repeatButton, speaking: true, speechPaused: false, guiding: true), .repeatLast)
    }

    func testScreenStaysAwakeWhileGuidingOrRecording() {
        var w = ScreenWakePolicy()
        XCTAssertNil(w.update(guiding: false, recording: false))
        XCTAssertEqual(w.update(guiding: true, recording: false), true)
        XCTAssertNil(w.update(guiding: true, recording: true))
        XCTAssertNil(w.update(guiding: false, recording: true), "still recording")
        XCTAssertEqual(w.update(guiding: false, recording: false), false)
    }

    // MARK: orientation coach

    func testAttitudeFromGravity() throws {
        let upright = try XCTUnwrap(PhoneAttitude(gravityX: 0, y: -1, z: 0))
        XCTAssertEqual(upright.cameraPitchDeg, 0, accuracy: 1e-9)
        XCTAssertEqual(upright.rollDeg, 0, accuracy: 1e-9)
        let flatScreenUp = try XCTUnwrap(PhoneAttitude(gravityX: 0, y: 0, z: -1))
        XCTAssertEqual(flatScreenUp.cameraPitchDeg, -90, accuracy: 1e-9, "back camera looks at the floor")
        // Top tilted 20 deg away from the traveler: camera 20 deg down.
        let a = 20 * Double.pi / 180
        XCTAssertEqual(try XCTUnwrap(PhoneAttitude(gravityX: 0, y: -cos(a), z: -sin(a))).cameraPitchDeg, -20, accuracy: 1e-9)
        // Top leaning 30 deg to the right (clockwise as the traveler sees the screen).
        let r = 30 * Double.pi / 180
        XCTAssertEqual(try XCTUnwrap(PhoneAttitude(gravityX: sin(r), y: -cos(r), z: 0)).rollDeg, 30, accuracy: 1e-9)
        XCTAssertNil(PhoneAttitude(gravityX: 0, y: 0, z: 0))
        XCTAssertNil(PhoneAttitude(gravityX: .nan, y: -1, z: 0))
    }

    func testCoachSpeaksCorrectionsThenCompletes() {
        var c = OrientationCoach(profile: .of(.handheld), phrases: phrases)
        var said: [(Double, String)] = []
        func feed(_ pitch: Double, _ roll: Double, from t0: Int, to t1: Int) {   // tenths of a second
            for i in t0..<t1 {
                let t = Double(i) / 10
                if let s = c.update(PhoneAttitude(cameraPitchDeg: pitch, rollDeg: roll), t: t) { said.append((t, s)) }
            }
        }
        feed(-45, 0, from: 0, to: 50)     // camera at the floor for 5 s
        feed(5, 35, from: 50, to: 60)     // leaning right
        feed(5, 0, from: 60, to: 100)     // right
        XCTAssertEqual(said.map(\.1), [phrases.text(.coachPitchDown), phrases.text(.coachPitchDown), phrases.text(.coachRollRight),
                                       phrases.text(.coachGood), phrases.text(.coachDone)])
        XCTAssertEqual(said[0].0, 0.6, accuracy: 0.01)
        XCTAssertEqual(said[1].0, 4.6, accuracy: 0.01)
        XCTAssertEqual(said.last!.0, 9.0, accuracy: 0.01)
        XCTAssertTrue(c.completed)
        XCTAssertEqual(OrientationCoach(profile: .of(.handheld), phrases: phrases).feedback(for: PhoneAttitude(cameraPitchDeg: 80, rollDeg: 0)), .flat)
        XCTAssertEqual(OnboardingStep.safety.next, .carry)
        XCTAssertNil(OnboardingStep.practice.next)
        XCTAssertEqual(OnboardingStep.hold.text(phrases, carry: .lanyard), phrases.text(.holdLanyard))
    }
}
