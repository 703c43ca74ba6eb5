// CoreMotion -> stridekit units and clock. iOS only; the conversions themselves live in
// StridekitPacking (Conversion.swift) and are tested without CoreMotion.
//
// Apple allows one CMMotionManager per app: pass yours if the app already has one.
// All handlers run on `queue` (serial), so raw streams are joined without locks.

#if canImport(CoreMotion) && os(iOS)
import CoreMotion
import Foundation
import StridekitPacking

public enum MotionSourceError: Error, CustomStringConvertible {
    case unavailable(String)

    public var description: String {
        switch self {
        case .unavailable(let what): return "\(what) is not available on this device"
        }
    }
}

public final class MotionSource {
    public enum ImuMode {
        /// `CMDeviceMotion`: gravity + user acceleration, bias-corrected rotation rate,
        /// calibrated magnetic field (absent while uncalibrated). One callback per sample.
        case deviceMotion
        /// The raw accelerometer, gyroscope and magnetometer streams, joined by
        /// `ImuAligner` (one record per accelerometer sample).
        case raw
    }

    public let manager: CMMotionManager
    public let queue: OperationQueue
    private let clock: MonotonicClock
    private var aligner = ImuAligner()

    public init(manager: CMMotionManager = CMMotionManager(), clock: MonotonicClock = .system) {
        self.manager = manager
        self.clock = clock
        queue = OperationQueue()
        queue.name = "io.stridekit.motion"
        queue.maxConcurrentOperationCount = 1
        queue.qualityOfService = .userInitiated
    }

    /// Accelerometer only (the PaceTracker's own step detector): `handler(t_s, m/s²)`.
    public func startAccelerometer(rateHz: Double = 100,
                                   handler: @escaping (Double, Vector3) -> Void) throws {
        guard manager.isAccelerometerAvailable else { throw MotionSourceError.unavailable("accelerometer") }
        manager.accelerometerUpdateInterval = 1.0 / rateHz
        let clock = self.clock
        manager.startAccelerometerUpdates(to: queue) { data, _ in
            guard let data else { return }
            let a = data.acceleration
            handler(clock.seconds(fromUptime: data.timestamp),
                    CoreMotionUnits.specificForceMps2(fromG: Vector3(a.x, a.y, a.z)))
        }
    }

    /// Full IMU records for `PhoneNavigator.pushImuPacked`.
    public func startImu(mode: ImuMode = .raw, rateHz: Double = 100,
                         handler: @escaping (ImuRecord) -> Void) throws {
        switch mode {
        case .deviceMotion:
            guard manager.isDeviceMotionAvailable else { throw MotionSourceError.unavailable("device motion") }
            manager.deviceMotionUpdateInterval = 1.0 / rateHz
            // The calibrated magnetic field is only filled in with a magnetic reference frame.
            let frame: CMAttitudeReferenceFrame =
                CMMotionManager.availableAttitudeReferenceFrames().contains(.xMagneticNorthZVertical)
                ? .xMagneticNorthZVertical : .xArbitraryZVertical
            let clock = self.clock
            manager.startDeviceMotionUpdates(using: frame, to: queue) { motion, _ in
                guard let m = motion else { return }
                let g = m.gravity, u = m.userAcceleration, w = m.rotationRate
                let field = m.magneticField
                let mag: Vector3? = field.accuracy == .uncalibrated
                    ? nil : Vector3(field.field.x, field.field.y, field.field.z)
                handler(ImuRecord(
                    tS: clock.seconds(fromUptime: m.timestamp),
                    gyroRads: Vector3(w.x, w.y, w.z),
                    accelMps2: CoreMotionUnits.specificForceMps2(
                        fromG: Vector3(g.x + u.x, g.y + u.y, g.z + u.z)),
                    magUt: mag))
            }
        case .raw:
            guard manager.isAccelerometerAvailable, manager.isGyroAvailable else {
                throw MotionSourceError.unavailable("accelerometer + gyroscope")
            }
            let interval = 1.0 / rateHz
            manager.accelerometerUpdateInterval = interval
            manager.gyroUpdateInterval = interval
            let clock = self.clock
            // Gyro first so the first accelerometer samples find one.
            manager.startGyroUpdates(to: queue) { [weak self] data, _ in
                guard let self, let data else { return }
                let w = data.rotationRate
                self.aligner.gyroscope(tS: clock.seconds(fromUptime: data.timestamp),
                                       rads: Vector3(w.x, w.y, w.z))
            }
            if manager.isMagnetometerAvailable {
                manager.magnetometerUpdateInterval = max(interval, 1.0 / 50)
                manager.startMagnetometerUpdates(to: queue) { [weak self] data, _ in
                    guard let self, let data else { return }
                    let f = data.magneticField  // µT, uncalibrated (hard-iron bias included)
                    self.aligner.magnetometer(tS: clock.seconds(fromUptime: data.timestamp),
                                              microtesla: Vector3(f.x, f.y, f.z))
                }
            }
            manager.startAccelerometerUpdates(to: queue) { [weak self] data, _ in
                guard let self, let data else { return }
                let a = data.acceleration
                if let record = self.aligner.accelerometer(
                    tS: clock.seconds(fromUptime: data.timestamp),
                    specificForceMps2: CoreMotionUnits.specificForceMps2(fromG: Vector3(a.x, a.y, a.z))) {
                    handler(record)
                }
            }
        }
    }

    public func stop() {
        manager.stopDeviceMotionUpdates()
        manager.stopAccelerometerUpdates()
        manager.stopGyroUpdates()
        manager.stopMagnetometerUpdates()
    }
}

/// CMPedometer cumulative step counts on stridekit's clock.
public final class PedometerSource {
    public let pedometer = CMPedometer()
    private let clock: MonotonicClock

    public init(clock: MonotonicClock = .system) {
        self.clock = clock
    }

    public static var isAvailable: Bool { CMPedometer.isStepCountingAvailable() }

    /// `handler(t_s, steps since start)` every few seconds (CoreMotion's pace), on a
    /// CoreMotion queue. `t_s` is `endDate` converted by `MonotonicClock`.
    public func start(from start: Date = Date(), handler: @escaping (Double, Int64) -> Void) throws {
        guard Self.isAvailable else { throw MotionSourceError.unavailable("step counting") }
        let clock = self.clock
        pedometer.startUpdates(from: start) { data, _ in
            guard let data else { return }
            handler(clock.seconds(from: data.endDate), data.numberOfSteps.int64Value)
        }
    }

    public func stop() {
        pedometer.stopUpdates()
    }
}
#endif
