// One monotonic clock for every stream stridekit sees on iOS. Foundation only.
//
// stridekit wants `t_s`: seconds on one monotonic clock, strictly increasing per
// stream, the same clock for GNSS and motion. On iOS that clock is
// `ProcessInfo.processInfo.systemUptime` (seconds since boot, mach_absolute_time
// based: never jumps, does not advance while the device sleeps):
//
// * CoreMotion (`CMLogItem.timestamp` of CMAccelerometerData, CMGyroData,
//   CMMagnetometerData, CMDeviceMotion) is already on this clock: used as is.
// * `CLLocation.timestamp` and `CMPedometerData.startDate/endDate` are `Date`s (wall
//   clock, which NTP or the user can step). A date is converted through its *age*:
//   `t = uptimeNow - (wallNow - date)`, both clocks read at conversion time. Locations
//   and pedometer updates are delivered within about a second of their timestamp, so
//   a wall-clock step between the event and its delivery is the only error source,
//   and it shows up only in that one sample. Cached locations (much older than
//   `maxLocationAge`) are dropped by `LocationConversion`.
//
// The values are absolute uptime seconds (no origin subtracted): f64 keeps
// sub-microsecond resolution for years of uptime, and snapshots taken before the app
// was killed stay on the same time base until the next reboot.

import Foundation

public struct MonotonicClock: Sendable {
    private let uptimeNow: @Sendable () -> TimeInterval
    private let wallNow: @Sendable () -> Date

    /// The device clocks: `ProcessInfo.systemUptime` and `Date()`.
    public static let system = MonotonicClock(
        uptimeNow: { ProcessInfo.processInfo.systemUptime },
        wallNow: { Date() })

    /// Clocks injected (tests).
    public init(uptimeNow: @escaping @Sendable () -> TimeInterval,
                wallNow: @escaping @Sendable () -> Date) {
        self.uptimeNow = uptimeNow
        self.wallNow = wallNow
    }

    /// Now, seconds.
    public func now() -> Double {
        uptimeNow()
    }

    /// A CoreMotion timestamp (`CMLogItem.timestamp`, seconds since boot): already on
    /// this clock.
    public func seconds(fromUptime timestamp: TimeInterval) -> Double {
        timestamp
    }

    /// A wall-clock `Date` (`CLLocation.timestamp`, `CMPedometerData.endDate`) on this
    /// clock: monotonic now minus the date's age.
    public func seconds(from date: Date) -> Double {
        uptimeNow() - wallNow().timeIntervalSince(date)
    }

    /// How old `date` is now, seconds (negative: in the future).
    public func age(of date: Date) -> TimeInterval {
        wallNow().timeIntervalSince(date)
    }
}
