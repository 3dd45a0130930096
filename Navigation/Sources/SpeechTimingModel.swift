// How long an utterance lasts when spoken, without a synthesizer: the announcement policy schedules from it
// (a "now" cue must end before the traveler reaches the turn) on every platform, the same on the phone as in
// `wayfinder replay` and `wayfinder eval`. A linear model over syllables and punctuation pauses, fitted by
// least squares to espeak-ng 1.51 at 175 words per minute on every phrase of the phrase books (438 texts,
// Tests/NavigationTests/EspeakMeasurements.swift; docs/navigation.md gives the figures), scaled by the rate.
import Foundation

/// Deterministic utterance-duration model: `fixed + perSyllable x syllables + perComma x commas +
/// perSentenceBreak x inner sentence ends + finalPause (when the text ends with . ! ?)`, seconds at
/// `referenceWordsPerMinute`, times `referenceWordsPerMinute / wordsPerMinute` at another rate. Syllables
/// are counted per word by vowel groups (English: a e i o u y, a final silent "e" dropped; Spanish: a e i o
/// u and accented vowels), numbers by their spoken words (0...999; English or Spanish).
public struct SpeechTimingModel: Sendable, Equatable, Codable {
    /// Phrase-book language whose syllable rules are used ("en", "es"; others count like English).
    public var language: String
    /// Seconds per utterance independent of its length (synthesizer start, leading silence).
    public var fixedSeconds: Double
    /// Seconds per syllable.
    public var secondsPerSyllable: Double
    /// Seconds of pause per comma, semicolon or colon.
    public var secondsPerComma: Double
    /// Seconds of pause per sentence end inside the text (". " between two sentences).
    public var secondsPerSentenceBreak: Double
    /// Seconds of trailing pause when the text ends with a full stop, "!" or "?".
    public var finalPauseSeconds: Double
    /// Speaking rate the coefficients were fitted at, words per minute (espeak-ng's default, 175).
    public var referenceWordsPerMinute: Double
    /// Speaking rate of the voice in use, words per minute (the phone passes its speech rate converted to
    /// words per minute; 175 = the reference).
    public var wordsPerMinute: Double

    /// Creates a model with explicit coefficients (seconds) at `wordsPerMinute`.
    public init(language: String, fixedSeconds: Double, secondsPerSyllable: Double, secondsPerComma: Double,
                secondsPerSentenceBreak: Double, finalPauseSeconds: Double, referenceWordsPerMinute: Double = 175,
                wordsPerMinute: Double = 175) {
        self.language = language; self.fixedSeconds = fixedSeconds; self.secondsPerSyllable = secondsPerSyllable
        self.secondsPerComma = secondsPerComma; self.secondsPerSentenceBreak = secondsPerSentenceBreak
        self.finalPauseSeconds = finalPauseSeconds; self.referenceWordsPerMinute = referenceWordsPerMinute
        self.wordsPerMinute = wordsPerMinute
    }

    /// English, fitted to espeak-ng 1.51 (`-v en -s 175`) on the 219 English texts: mean absolute error
    /// 0.13 s, 95th percentile 0.32 s, largest 0.51 s.
    public static let espeakEnglish = SpeechTimingModel(language: "en", fixedSeconds: 0.398, secondsPerSyllable: 0.1686,
                                                        secondsPerComma: 0.291, secondsPerSentenceBreak: 0.584,
                                                        finalPauseSeconds: 0.250)
    /// Spanish, fitted to espeak-ng 1.51 (`-v es -s 175`) on the 219 Spanish texts: mean absolute error
    /// 0.14 s, 95th percentile 0.32 s, largest 0.44 s.
    public static let espeakSpanish = SpeechTimingModel(language: "es", fixedSeconds: 0.411, secondsPerSyllable: 0.1268,
                                                        secondsPerComma: 0.315, secondsPerSentenceBreak: 0.605,
                                                        finalPauseSeconds: 0.132)

    /// The calibrated model for a phrase-book language ("es", "es-MX" -> Spanish; anything else English)
    /// at `wordsPerMinute`.
    public static func calibrated(language: String, wordsPerMinute: Double = 175) -> SpeechTimingModel {
        let base = language.lowercased().hasPrefix("es") ? espeakSpanish : espeakEnglish
        var m = base
        m.language = language
        m.wordsPerMinute = wordsPerMinute
        return m
    }

    /// Estimated duration of `text`, seconds (0 for text with nothing to say).
    public func durationSeconds(_ text: String) -> Double {
        let f = Self.features(text, language: language)
        guard f.syllables > 0 else { return 0 }
        let atReference = fixedSeconds + secondsPerSyllable * Double(f.syllables) + secondsPerComma * Double(f.commas)
            + secondsPerSentenceBreak * Double(f.sentenceBreaks) + (f.endsSentence ? finalPauseSeconds : 0)
        let rate = wordsPerMinute.isFinite && wordsPerMinute > 0 ? wordsPerMinute : referenceWordsPerMinute
        return atReference * referenceWordsPerMinute / rate
    }

    /// What the model counts in a text.
    public struct Features: Sendable, Equatable {
        /// Syllables of the words and spoken numbers.
        public var syllables: Int
        /// Commas, semicolons and colons.
        public var commas: Int
        /// Sentence ends followed by more text.
        public var sentenceBreaks: Int
        /// True when the text ends with ". ", "!" or "?" (trailing spaces ignored).
        public var endsSentence: Bool
    }

    /// Counts syllables and pauses of `text` under the syllable rules of `language`.
    public static func features(_ text: String, language: String) -> Features {
        let spanish = language.lowercased().hasPrefix("es")
        var syllables = 0, commas = 0, breaks = 0
        var word = "", digits = ""
        func endToken() {
            if !digits.isEmpty {
                syllables += Int(digits).map { numberSyllables($0, spanish: spanish) } ?? 2 * digits.count
                digits = ""
            }
            if !word.isEmpty {
                syllables += wordSyllables(word, spanish: spanish)
                word = ""
            }
        }
        let chars = Array(text)
        for (i, c) in chars.enumerated() {
            if c.isLetter || (c == "'" && !word.isEmpty && i + 1 < chars.count && chars[i + 1].isLetter) {
                if !digits.isEmpty { endToken() }
                word.append(c)
            } else if c.isNumber, c.isASCII {
                if !word.isEmpty { endToken() }
                digits.append(c)
            } else {
                endToken()
                if c == "," || c == ";" || c == ":" { commas += 1 }
                if c == "." || c == "!" || c == "?", i + 1 < chars.count, chars[i + 1].isWhitespace,
                   chars[(i + 1)...].contains(where: { !$0.isWhitespace }) {
                    breaks += 1
                }
            }
        }
        endToken()
        let trimmed = text.trimmingCharacters(in: .whitespacesAndNewlines)
        let ends = trimmed.last.map { $0 == "." || $0 == "!" || $0 == "?" } ?? false
        return Features(syllables: syllables, commas: commas, sentenceBreaks: breaks, endsSentence: ends)
    }

    /// Syllables of one word: its vowel groups, at least 1 (English: "y" is a vowel and a final "e" after
    /// another vowel group is silent, except in "-le").
    static func wordSyllables(_ word: String, spanish: Bool) -> Int {
        let w = word.lowercased()
        let vowels: Set<Character> = spanish ? ["a", "e", "i", "o", "u", "á", "é", "í", "ó", "ú", "ü"]
            : ["a", "e", "i", "o", "u", "y"]
        var groups = 0
        var inGroup = false
        for c in w {
            let v = vowels.contains(c)
            if v && !inGroup { groups += 1 }
            inGroup = v
        }
        if !spanish, groups > 1, w.hasSuffix("e"), !w.hasSuffix("le") { groups -= 1 }
        return max(1, groups)
    }

    private static let englishUnits = [2, 1, 1, 1, 1, 1, 1, 2, 1, 1, 1, 3, 1, 2, 2, 2, 2, 3, 2, 2]
    private static let englishTens = [0, 0, 2, 2, 2, 2, 2, 3, 2, 2]
    private static let spanishUnits = [2, 2, 1, 1, 2, 2, 1, 2, 2, 2, 1, 2, 2, 2, 3, 2, 4, 5, 4, 5]
    private static let spanishTens = [0, 0, 2, 3, 3, 4, 4, 4, 3, 3]

    /// Syllables of a whole number as spoken ("twenty five" = 3, "veinticinco" counted as "veinte y cinco" =
    /// 5); beyond 999, two per digit.
    static func numberSyllables(_ n: Int, spanish: Bool) -> Int {
        let units = spanish ? spanishUnits : englishUnits
        let tens = spanish ? spanishTens : englishTens
        if n < 0 { return 2 + numberSyllables(-n, spanish: spanish) }
        if n < 20 { return units[n] }
        if n < 100 { return tens[n / 10] + (n % 10 == 0 ? 0 : units[n % 10] + (spanish ? 1 : 0)) }
        if n < 1000 {
            let hundreds = spanish ? 3 : units[n / 100] + 2
            return hundreds + (n % 100 == 0 ? 0 : numberSyllables(n % 100, spanish: spanish))
        }
        return 2 * String(n).count
    }
}
