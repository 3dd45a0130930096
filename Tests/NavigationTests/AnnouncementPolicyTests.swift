import Foundation
import XCTest
@testable import Navigation

final class AnnouncementPolicyTests: XCTestCase {
    private func texts(_ e: [TimedGuidanceEvent]) -> [String] { e.compactMap(\.spokenText) }

    func testEventDescription() {
        XCTAssertEqual(TimedGuidanceEvent(t: 12.3, event: .speak(text: "Turn left now.", priority: .cue, interrupt: true)).description,
                       "12.30 s  speak cue!         Turn left now.")
        XCTAssertEqual(TimedGuidanceEvent(t: 1, event: .haptic(.wrongWay)).description, "1.00 s  haptic wrongWay")
    }

    func testDurationFromSpeechTimingModel() {
        let p = AnnouncementPolicy()
        // "In 8 meters, turn left.": 6 syllables (in, eight, me-ters, turn, left), one comma, final stop.
        XCTAssertEqual(p.estimatedDurationSeconds("In 8 meters, turn left."), 0.398 + 6 * 0.1686 + 0.291 + 0.250,
                       accuracy: 1e-9)
        XCTAssertEqual(p.estimatedDurationSeconds(""), 0.5, "minimum utterance")
    }

    func testEarliestStartWaitsOnlyForSpeechItCannotCutOff() {
        let p = AnnouncementPolicy()
        p.submit("In 8 meters, turn right.", priority: .alert, t: 0)
        XCTAssertEqual(texts(p.flush(t: 0)), ["In 8 meters, turn right."])
        let end = p.speakingUntil
        XCTAssertGreaterThan(end, 1.5)
        XCTAssertEqual(p.earliestStart(priority: .cue, t: 0.5), 0.5, "a cue interrupts an alert")
        XCTAssertEqual(p.earliestStart(priority: .alert, t: 0.5), end, "an alert waits for the alert")
        XCTAssertEqual(p.earliestStart(priority: .alert, t: end + 0.1), end + 0.1, "silence: now")
    }

    func testSafetyAndCueInterruptInformationWaits() {
        let p = AnnouncementPolicy()
        p.submit("Continue fifteen meters along here.", priority: .information, t: 0)  // 5 words: 2 s
        XCTAssertEqual(texts(p.flush(t: 0)), ["Continue fifteen meters along here."])
        p.submit("Turn left now.", priority: .cue, t: 0.5)
        let cue = p.flush(t: 0.5)
        XCTAssertEqual(cue, [TimedGuidanceEvent(t: 0.5, event: .speak(text: "Turn left now.", priority: .cue, interrupt: true))])
        // An alert does not interrupt the cue (1.2 s long): it waits for silence.
        p.submit("In 8 meters, turn right.", priority: .alert, t: 0.6)
        XCTAssertEqual(texts(p.flush(t: 0.6)), [])
        XCTAssertEqual(texts(p.flush(t: 1.6)), [])
        let later = p.flush(t: 1.7)
        XCTAssertEqual(later, [TimedGuidanceEvent(t: 1.7, event: .speak(text: "In 8 meters, turn right.", priority: .alert, interrupt: false))])
        // Safety interrupts the alert.
        p.submit("Wrong way, turn around.", priority: .safety, t: 2.0)
        XCTAssertEqual(p.flush(t: 2.0), [TimedGuidanceEvent(t: 2.0, event: .speak(text: "Wrong way, turn around.", priority: .safety, interrupt: true))])
        // A cue does not interrupt safety; it waits and, 1.5 s old, is dropped as stale.
        p.submit("Turn right now.", priority: .cue, t: 2.1)
        XCTAssertEqual(texts(p.flush(t: 2.1)), [])
        XCTAssertEqual(texts(p.flush(t: 3.7)), [], "stale cue dropped, not spoken late")
    }

    func testSupersededAdviceStopsAndTheNextUtteranceInterruptsIt() {
        let p = AnnouncementPolicy()
        p.submit("I'm not sure where you are yet; keep walking slowly.", priority: .information, t: 0)
        XCTAssertEqual(texts(p.flush(t: 0)), ["I'm not sure where you are yet; keep walking slowly."])
        p.submit("Start walking.", priority: .information, t: 0.2)  // queued behind it: no longer holds either
        XCTAssertEqual(p.earliestStart(priority: .alert, t: 0.5), p.speakingUntil, "an alert waits for the advice")
        p.supersede(upTo: .information, t: 0.5)
        XCTAssertEqual(p.earliestStart(priority: .alert, t: 0.5), 0.5, "the advice is over")
        p.submit("Go straight ahead, 10 meters.", priority: .alert, t: 0.5)
        XCTAssertEqual(p.flush(t: 0.5), [TimedGuidanceEvent(t: 0.5, event: .speak(text: "Go straight ahead, 10 meters.",
                                                                                  priority: .alert, interrupt: true))])
        XCTAssertEqual(texts(p.flush(t: 10)), [], "the queued information was dropped")
        // Something more important than the bound, or an answer to the traveler, is left to play.
        p.submit("Turn left now.", priority: .cue, t: 11)
        XCTAssertEqual(texts(p.flush(t: 11)), ["Turn left now."])
        p.supersede(upTo: .information, t: 11.3)
        XCTAssertEqual(p.earliestStart(priority: .alert, t: 11.3), p.speakingUntil)
        p.submit("Near room 107.", priority: .information, t: 20, requested: true)
        XCTAssertEqual(texts(p.flush(t: 20)), ["Near room 107."])
        p.supersede(upTo: .information, t: 20.3)
        XCTAssertEqual(p.earliestStart(priority: .alert, t: 20.3), p.speakingUntil)
    }

    func testACueDoesNotCutOffAnotherCue() {
        let p = AnnouncementPolicy()
        p.submit("Turn right now.", priority: .cue, t: 0)  // 1.2 s
        XCTAssertEqual(texts(p.flush(t: 0)), ["Turn right now."])
        p.submit("Go through the door now.", priority: .cue, t: 0.4)
        XCTAssertEqual(texts(p.flush(t: 0.4)), [], "waits for the first cue to end")
        XCTAssertEqual(p.flush(t: 1.2), [TimedGuidanceEvent(t: 1.2, event: .speak(text: "Go through the door now.", priority: .cue, interrupt: true))])
        // Equal texts with different repeat keys are both said; the same key is suppressed.
        p.submit("Go through the door now.", priority: .cue, t: 5, repeatKey: "door B")
        XCTAssertEqual(texts(p.flush(t: 5)), ["Go through the door now."])
        p.submit("Go through the door now.", priority: .cue, t: 7, repeatKey: "door B")
        XCTAssertEqual(texts(p.flush(t: 7)), [])
        // A queued message is withdrawn by key prefix.
        p.submit("A long message to keep the channel busy for a while now.", priority: .safety, t: 20)
        _ = p.flush(t: 20)
        p.submit("In 2 meters, take the stairs.", priority: .alert, t: 20.1, repeatKey: "alert:stairs")
        p.discardPending(repeatKeyPrefix: "alert:")
        XCTAssertEqual(texts(p.flush(t: 30)), [])
    }

    func testHighestPriorityFirstWhenSubmittedTogether() {
        let p = AnnouncementPolicy()
        p.submit("Start walking.", priority: .information, t: 0)
        p.submit("In 5 meters, turn left.", priority: .alert, t: 0)
        p.submit("Turn right now.", priority: .cue, t: 0)
        XCTAssertEqual(texts(p.flush(t: 0)), ["Turn right now."])
        XCTAssertEqual(texts(p.flush(t: 1.2)), ["In 5 meters, turn left."])
        // Information: silence after the alert (ends 3.2), no previous informational message.
        XCTAssertEqual(texts(p.flush(t: 3.1)), [])
        XCTAssertEqual(texts(p.flush(t: 3.2)), ["Start walking."])
    }

    func testInformationSpacing() {
        let p = AnnouncementPolicy()
        p.submit("Continue 10 meters.", priority: .information, t: 0)
        p.submit("Go straight ahead, 5 meters.", priority: .information, t: 0)
        XCTAssertEqual(texts(p.flush(t: 0)), ["Continue 10 meters."])
        let end = p.speakingUntil
        XCTAssertEqual(end, p.estimatedDurationSeconds("Continue 10 meters."), accuracy: 1e-12)
        XCTAssertEqual(texts(p.flush(t: end + 0.1)), [], "speech ended but 1.5 s spacing applies")
        XCTAssertEqual(texts(p.flush(t: end + 1.45)), [])
        XCTAssertEqual(texts(p.flush(t: end + 1.55)), ["Go straight ahead, 5 meters."])
    }

    func testStalenessPerPriority() {
        let p = AnnouncementPolicy()
        p.submit("A long informational message of exactly ten words here.", priority: .information, t: 0)
        XCTAssertEqual(texts(p.flush(t: 0)).count, 1)  // speaking until 4 s
        p.submit("In 8 meters, turn left.", priority: .alert, t: 0.1)
        // Alert waits; at 4.0 it is 3.9 s old: still fresh.
        XCTAssertEqual(texts(p.flush(t: 4.0)), ["In 8 meters, turn left."])
        p.submit("Ten more words to keep the speaker busy for four seconds.", priority: .cue, t: 4.1)
        XCTAssertEqual(texts(p.flush(t: 4.1)).count, 1)  // cue interrupts the alert
        p.submit("In 6 meters, turn right.", priority: .alert, t: 4.2)
        XCTAssertLessThan(p.speakingUntil, 8.3, "the cue is over by then")
        XCTAssertEqual(texts(p.flush(t: 8.3)), [], "alert older than 4 s dropped")
    }

    func testRepeatSuppressionUnlessRequested() {
        let p = AnnouncementPolicy()
        p.submit("Continue 10 meters.", priority: .information, t: 0)
        XCTAssertEqual(texts(p.flush(t: 0)).count, 1)
        p.submit("Continue 10 meters.", priority: .information, t: 5)
        XCTAssertEqual(texts(p.flush(t: 5)), [], "same text within 10 s")
        p.submit("Continue 10 meters.", priority: .information, t: 6, requested: true)
        XCTAssertEqual(p.flush(t: 6), [TimedGuidanceEvent(t: 6, event: .speak(text: "Continue 10 meters.", priority: .information, interrupt: true))])
        p.submit("Continue 10 meters.", priority: .information, t: 16.5)
        XCTAssertEqual(texts(p.flush(t: 16.5)), ["Continue 10 meters."], "10 s after the last time it was spoken")
    }

    func testHapticsPassThroughWhileSpeaking() {
        let p = AnnouncementPolicy()
        p.submit("A message that takes a few seconds to say.", priority: .safety, t: 0)
        _ = p.flush(t: 0)
        p.submitHaptic(.wrongWay)
        p.submit("Another informational message.", priority: .information, t: 0.2)
        XCTAssertEqual(p.flush(t: 0.2), [TimedGuidanceEvent(t: 0.2, event: .haptic(.wrongWay))])
    }
}
