#if os(iOS)
import Foundation
import WayfinderCore

/// Persists `AppSettings` (shared, Codable, lenient) as JSON in UserDefaults under
/// `AppSettings.userDefaultsKey`. An unreadable value gives the defaults and a logged warning.
enum SettingsStore {
    static func load() -> AppSettings {
        let (settings, warning) = AppSettings.decode(UserDefaults.standard.data(forKey: AppSettings.userDefaultsKey))
        if let warning { NSLog("Wayfinder: %@", warning) }
        return settings
    }

    static func save(_ settings: AppSettings) {
        UserDefaults.standard.set(settings.sanitized().encoded(), forKey: AppSettings.userDefaultsKey)
    }
}
#endif
