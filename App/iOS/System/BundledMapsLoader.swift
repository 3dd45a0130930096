#if os(iOS)
import Foundation
import Maps

/// Loads the buildings shipped in the app bundle (Maps/Buildings/*.json, copied as resources by project.yml).
enum BundledMapsLoader {
    static func all() -> [Building] {
        let urls = Bundle.main.urls(forResourcesWithExtension: "json", subdirectory: "Buildings") ?? []
        return urls.compactMap { try? MapLoader.load(contentsOf: $0) }.sorted { $0.name < $1.name }
    }
}
#endif
