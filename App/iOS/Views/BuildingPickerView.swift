#if canImport(SwiftUI) && canImport(ARKit) && os(iOS)
import Maps
import SwiftUI
import UniformTypeIdentifiers

/// Choose a bundled building or open a map file from Files.
struct BuildingPickerView: View {
    @EnvironmentObject var model: AppModel
    @State private var importing = false

    var body: some View {
        List {
            Section("Buildings") {
                ForEach(model.bundledBuildings, id: \.id) { building in
                    Button(building.name) { model.select(building: building) }
                        .accessibilityHint("Choose this building")
                }
            }
            Section {
                Button("Open a map from Files") { importing = true }
                    .accessibilityHint("Opens the Files browser to choose a Wayfinder map file")
            }
        }
        .navigationTitle("Building")
        .fileImporter(isPresented: $importing, allowedContentTypes: [.json]) { result in
            guard case .success(let url) = result else { return }
            let scoped = url.startAccessingSecurityScopedResource()
            defer { if scoped { url.stopAccessingSecurityScopedResource() } }
            do { model.select(building: try MapLoader.load(contentsOf: url)) } catch { model.lastError = "\(error)" }
        }
        .alert("Map not loaded", isPresented: .constant(model.lastError != nil)) {
            Button("OK") { model.lastError = nil }
        } message: { Text(model.lastError ?? "") }
    }
}
#endif
