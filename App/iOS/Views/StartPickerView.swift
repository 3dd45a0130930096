#if canImport(SwiftUI) && canImport(ARKit) && os(iOS)
import SwiftUI
import WayfinderCore

/// Choose where the traveler is, or "I don't know where I am" (the localizer then starts from the floor).
struct StartPickerView: View {
    @EnvironmentObject var model: AppModel
    @State private var query = ""

    var body: some View {
        List {
            Button("I don't know where I am") { model.selectStart(nil) }
                .font(.title3)
                .accessibilityHint("Wayfinder will find your position as you walk")
            ForEach(model.snapshot.places?.search(query) ?? []) { place in
                Button(place.name) { model.selectStart(place.id) }
                    .accessibilityLabel(place.accessibilityLabel)
            }
        }
        .searchable(text: $query, prompt: "Search places")
        .navigationTitle("Where are you?")
    }
}
#endif
