// CoreLocation -> GNSS fixes on stridekit's clock (conversion rules: Conversion.swift).

#if canImport(CoreLocation)
import CoreLocation
import Foundation
import StridekitPacking

extension LocationReading {
    /// The fields of `location` stridekit uses.
    public init(_ location: CLLocation) {
        self.init(timestamp: location.timestamp,
                  latitude: location.coordinate.latitude,
                  longitude: location.coordinate.longitude,
                  altitude: location.altitude,
                  verticalAccuracy: location.verticalAccuracy,
                  horizontalAccuracy: location.horizontalAccuracy,
                  speed: location.speed,
                  speedAccuracy: location.speedAccuracy)
    }
}

/// Delivers converted fixes from a `CLLocationManager`. Create it on a thread with a
/// run loop (the main thread): CoreLocation calls the delegate there. The app owns
/// the usage-description keys (NSLocationWhenInUseUsageDescription) and, for runs
/// with the screen off, the `location` background mode.
public final class LocationSource: NSObject, CLLocationManagerDelegate {
    public let manager: CLLocationManager
    private let clock: MonotonicClock
    private let handler: ([FixRecord]) -> Void

    public init(manager: CLLocationManager = CLLocationManager(), clock: MonotonicClock = .system,
                handler: @escaping ([FixRecord]) -> Void) {
        self.manager = manager
        self.clock = clock
        self.handler = handler
        super.init()
    }

    public func start() {
        manager.delegate = self
        manager.desiredAccuracy = kCLLocationAccuracyBest
        manager.distanceFilter = kCLDistanceFilterNone
        manager.activityType = .fitness
        if manager.authorizationStatus == .notDetermined {
            manager.requestWhenInUseAuthorization()
        }
        manager.startUpdatingLocation()
    }

    public func stop() {
        manager.stopUpdatingLocation()
    }

    public func locationManager(_ manager: CLLocationManager, didUpdateLocations locations: [CLLocation]) {
        let fixes = locations.compactMap {
            LocationConversion.fixRecord(LocationReading($0), clock: clock)
        }
        if !fixes.isEmpty { handler(fixes) }
    }

    public func locationManager(_ manager: CLLocationManager, didFailWithError error: Error) {
        // kCLErrorLocationUnknown is transient; CoreLocation keeps trying. Nothing to push.
    }
}
#endif
