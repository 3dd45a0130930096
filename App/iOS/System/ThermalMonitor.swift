#if canImport(UIKit) && os(iOS)
import Foundation
import UIKit
import WayfinderCore

/// Watches the thermal state and low-power mode / battery level and reports them to the detector
/// scheduler, which lowers the detector rate when the phone gets hot.
final class ThermalMonitor {
    var onChange: ((ThermalLevel, Bool) -> Void)?
    private var observers: [NSObjectProtocol] = []

    func start() {
        UIDevice.current.isBatteryMonitoringEnabled = true
        let center = NotificationCenter.default
        for name in [ProcessInfo.thermalStateDidChangeNotification, Notification.Name.NSProcessInfoPowerStateDidChange,
                     UIDevice.batteryLevelDidChangeNotification] {
            observers.append(center.addObserver(forName: name, object: nil, queue: .main) { [weak self] _ in self?.report() })
        }
        report()
    }

    func stop() {
        observers.forEach(NotificationCenter.default.removeObserver)
        observers.removeAll()
    }

    private func report() {
        let level: ThermalLevel
        switch ProcessInfo.processInfo.thermalState {
        case .nominal: level = .nominal
        case .fair: level = .fair
        case .serious: level = .serious
        case .critical: level = .critical
        @unknown default: level = .serious
        }
        let battery = UIDevice.current.batteryLevel
        onChange?(level, ProcessInfo.processInfo.isLowPowerModeEnabled || (battery >= 0 && battery < 0.2))
    }
}
#endif
