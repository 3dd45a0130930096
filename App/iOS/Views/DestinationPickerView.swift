#if canImport(SwiftUI) && canImport(ARKit) && os(iOS)
import SwiftUI
import WayfinderCore

/// Searchable list of labelled destinations.
struct DestinationPickerView: View {
    @EnvironmentObject var model: AppModel
    @State private var query = ""

    var body: some View {
        List(model.snapshot.places?.search(query) ?? []) { place in
            Button(place.name) { model.selectDestination(place.id) }
                .accessibilityLabel(place.accessibilityLabel)
                .accessibilityHint("Choose as destination")
        }
        .searchable(text: $query, prompt: "Search destinations")
        .navigationTitle("Destination")
    }
}
#endif
