// Platform values -> stridekit units, without importing CoreMotion or CoreLocation:
// the adapters in StridekitKit copy the platform objects' fields into these plain
// structs, so every rule here is tested anywhere.

import Foundation

public enum CoreMotionUnits {
    /// Standard gravity, m/s² per g.
    public static let standardGravity = 9.80665

    /// CoreMotion acceleration (`CMAccelerometerData.acceleration`, or
    /// `CMDeviceMotion.gravity + userAcceleration`) -> specific force in m/s².
    ///
    /// CoreMotion reports g and the opposite sign of specific force: a phone lying
    /// face up reads z = -1 g, while stridekit (like Android's TYPE_ACCELEROMETER)
    /// expects +9.81 m/s² on z. Hence the minus sign. Rotation rate (rad/s) and
    /// magnetic field (µT) need no conversion; the device axes are the same as
    /// Android's (x right, y to the top edge, z out of the screen).
    public static func specificForceMps2(fromG a: Vector3) -> Vector3 {
        -a * standardGravity
    }
}

/// The fields of a `CLLocation` stridekit uses (CoreLocation's units and sentinels).
public struct LocationReading: Equatable, Sendable {
    public var timestamp: Date
    public var latitude: Double
    public var longitude: Double
    /// Metres; valid only when `verticalAccuracy > 0`.
    public var altitude: Double
    public var verticalAccuracy: Double
    /// Metres; negative means the coordinate is invalid.
    public var horizontalAccuracy: Double
    /// m/s; negative means unknown.
    public var speed: Double
    /// m/s; negative means unknown.
    public var speedAccuracy: Double

    public init(timestamp: Date, latitude: Double, longitude: Double, altitude: Double,
                verticalAccuracy: Double, horizontalAccuracy: Double, speed: Double,
                speedAccuracy: Double) {
        self.timestamp = timestamp
        self.latitude = latitude
        self.longitude = longitude
        self.altitude = altitude
        self.verticalAccuracy = verticalAccuracy
        self.horizontalAccuracy = horizontalAccuracy
        self.speed = speed
        self.speedAccuracy = speedAccuracy
    }
}

public enum LocationConversion {
    /// Locations older than this when converted are cached fixes, not live ones.
    public static let maxLocationAge: TimeInterval = 10

    /// A fix on `clock`, or nil for an invalid coordinate or a stale (cached) location.
    public static func fixRecord(_ r: LocationReading, clock: MonotonicClock,
                                 maxAge: TimeInterval = maxLocationAge) -> FixRecord? {
        guard r.horizontalAccuracy >= 0, clock.age(of: r.timestamp) <= maxAge else {
            return nil
        }
        let hasSpeed = r.speed >= 0 && r.speedAccuracy >= 0
        return FixRecord(
            tS: clock.seconds(from: r.timestamp),
            latDeg: r.latitude,
            lonDeg: r.longitude,
            altM: r.verticalAccuracy > 0 ? r.altitude : nil,
            horizontalAccuracyM: r.horizontalAccuracy,
            speedMps: hasSpeed ? r.speed : nil,
            speedAccuracyMps: hasSpeed ? r.speedAccuracy : nil)
    }
}

/// Joins the three raw CoreMotion streams (accelerometer, gyroscope, magnetometer:
/// separate callbacks, separate timestamps) into 80-byte IMU records: one record per
/// accelerometer sample, with the newest gyroscope sample (zero-order hold) and the
/// newest magnetometer sample if it is recent enough (else no magnetometer, NaN).
public struct ImuAligner: Sendable {
    /// A gyroscope sample older than this (s) is not used: no record is produced.
    public var maxGyroAge: Double
    /// A magnetometer sample older than this (s) is reported as absent.
    public var maxMagAge: Double
    private var gyro: (t: Double, v: Vector3)?
    private var mag: (t: Double, v: Vector3)?

    public init(maxGyroAge: Double = 0.05, maxMagAge: Double = 0.25) {
        self.maxGyroAge = maxGyroAge
        self.maxMagAge = maxMagAge
    }

    public mutating func gyroscope(tS: Double, rads: Vector3) {
        gyro = (tS, rads)
    }

    public mutating func magnetometer(tS: Double, microtesla: Vector3) {
        mag = (tS, microtesla)
    }

    /// The record for this accelerometer sample, or nil while no fresh gyroscope sample
    /// is known.
    public mutating func accelerometer(tS: Double, specificForceMps2: Vector3) -> ImuRecord? {
        guard let g = gyro, abs(tS - g.t) <= maxGyroAge else { return nil }
        var m: Vector3?
        if let mm = mag, abs(tS - mm.t) <= maxMagAge { m = mm.v }
        return ImuRecord(tS: tS, gyroRads: g.v, accelMps2: specificForceMps2, magUt: m)
    }
}

/// Collects packed records and hands them out in batches: when `maxRecords` are
/// buffered or the oldest buffered record is `maxLatencyS` older than the newest
/// (sample time). Not thread-safe: own it from one queue.
public struct RecordBatcher: Sendable {
    public let recordBytes: Int
    public let maxRecords: Int
    public let maxLatencyS: Double
    private var buffer = Data()
    private var firstTS: Double?

    public init(recordBytes: Int, maxRecords: Int, maxLatencyS: Double) {
        precondition(recordBytes > 0 && maxRecords > 0)
        self.recordBytes = recordBytes
        self.maxRecords = maxRecords
        self.maxLatencyS = maxLatencyS
        buffer.reserveCapacity(recordBytes * maxRecords)
    }

    public var count: Int { buffer.count / recordBytes }

    /// Appends one record written by `write` (exactly `recordBytes` bytes); returns a
    /// batch to push when one is due.
    public mutating func add(tS: Double, _ write: (inout Data) -> Void) -> Data? {
        let before = buffer.count
        write(&buffer)
        precondition(buffer.count - before == recordBytes,
                     "a record must be \(recordBytes) bytes, got \(buffer.count - before)")
        if firstTS == nil { firstTS = tS }
        if count >= maxRecords || tS - (firstTS ?? tS) >= maxLatencyS {
            return flush()
        }
        return nil
    }

    /// Everything buffered (nil if empty); the batcher is empty afterwards.
    public mutating func flush() -> Data? {
        guard !buffer.isEmpty else { return nil }
        let out = buffer
        buffer = Data()
        buffer.reserveCapacity(recordBytes * maxRecords)
        firstTS = nil
        return out
    }
}
