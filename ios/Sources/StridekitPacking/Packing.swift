// Packed little-endian sample records, byte for byte the layouts the Rust bindings
// decode (bindings/src/packed.rs holds every layout). Foundation only: no
// CoreMotion, no Stridekit import, so this file compiles and is tested anywhere.
//
// ios/check-generated.py (run by scripts/test) compares every `recordBytes` and
// `fields` list below with the Rust constants and decoders.

import Foundation

/// A three-axis reading.
public struct Vector3: Equatable, Sendable {
    public var x: Double
    public var y: Double
    public var z: Double

    public init(_ x: Double, _ y: Double, _ z: Double) {
        self.x = x
        self.y = y
        self.z = z
    }

    public static func * (v: Vector3, k: Double) -> Vector3 {
        Vector3(v.x * k, v.y * k, v.z * k)
    }

    public static func + (a: Vector3, b: Vector3) -> Vector3 {
        Vector3(a.x + b.x, a.y + b.y, a.z + b.z)
    }

    public static prefix func - (v: Vector3) -> Vector3 {
        Vector3(-v.x, -v.y, -v.z)
    }
}

/// Appends `value` as 8 little-endian bytes (IEEE 754 bit pattern).
@inline(__always)
public func appendLittleEndian(_ value: Double, to data: inout Data) {
    withUnsafeBytes(of: value.bitPattern.littleEndian) { data.append(contentsOf: $0) }
}

/// Appends `value` as 8 little-endian bytes.
@inline(__always)
public func appendLittleEndian(_ value: UInt64, to data: inout Data) {
    withUnsafeBytes(of: value.littleEndian) { data.append(contentsOf: $0) }
}

/// Reads the f64 at `offset` of `data` (tests and diagnostics).
public func readLittleEndianDouble(_ data: Data, at offset: Int) -> Double {
    var bits: UInt64 = 0
    for i in 0..<8 {
        bits |= UInt64(data[data.startIndex + offset + i]) << (8 * UInt64(i))
    }
    return Double(bitPattern: bits)
}

/// `PaceTracker.pushAccelPacked`: 32 bytes, `t_s, ax, ay, az` as f64 (m/s², gravity
/// included). Rust: `packed::ACCEL_RECORD_BYTES`.
public enum AccelLayout {
    public static let recordBytes = 32
    public static let fields = ["t_s", "x_mps2", "y_mps2", "z_mps2"]

    public static func append(tS: Double, specificForceMps2 a: Vector3, to data: inout Data) {
        appendLittleEndian(tS, to: &data)
        appendLittleEndian(a.x, to: &data)
        appendLittleEndian(a.y, to: &data)
        appendLittleEndian(a.z, to: &data)
    }
}

/// `PaceTracker.pushStepCountsPacked`: 16 bytes, `t_s` f64 then the cumulative `steps`
/// i64 (≥ 0; the Kotlin/Swift `StepSample.count` type). Rust:
/// `packed::STEP_COUNT_RECORD_BYTES`.
public enum StepCountLayout {
    public static let recordBytes = 16
    public static let fields = ["t_s", "steps"]

    public static func append(tS: Double, steps: Int64, to data: inout Data) {
        appendLittleEndian(tS, to: &data)
        appendLittleEndian(UInt64(bitPattern: steps), to: &data)
    }
}

/// A GNSS fix as plain values (the Stridekit `GnssFix` record without the import).
public struct FixRecord: Equatable, Sendable {
    public var tS: Double
    public var latDeg: Double
    public var lonDeg: Double
    public var altM: Double?
    public var horizontalAccuracyM: Double?
    public var speedMps: Double?
    public var speedAccuracyMps: Double?

    public init(tS: Double, latDeg: Double, lonDeg: Double, altM: Double? = nil,
                horizontalAccuracyM: Double? = nil, speedMps: Double? = nil,
                speedAccuracyMps: Double? = nil) {
        self.tS = tS
        self.latDeg = latDeg
        self.lonDeg = lonDeg
        self.altM = altM
        self.horizontalAccuracyM = horizontalAccuracyM
        self.speedMps = speedMps
        self.speedAccuracyMps = speedAccuracyMps
    }
}

/// `PaceTracker.pushFixesPacked`: 56 bytes, seven f64; an absent optional is NaN.
/// Rust: `packed::FIX_RECORD_BYTES`.
public enum FixLayout {
    public static let recordBytes = 56
    public static let fields = ["t_s", "lat_deg", "lon_deg", "alt_m", "horizontal_accuracy_m",
                                "speed_mps", "speed_accuracy_mps"]

    public static func append(_ f: FixRecord, to data: inout Data) {
        appendLittleEndian(f.tS, to: &data)
        appendLittleEndian(f.latDeg, to: &data)
        appendLittleEndian(f.lonDeg, to: &data)
        appendLittleEndian(f.altM ?? .nan, to: &data)
        appendLittleEndian(f.horizontalAccuracyM ?? .nan, to: &data)
        appendLittleEndian(f.speedMps ?? .nan, to: &data)
        appendLittleEndian(f.speedAccuracyMps ?? .nan, to: &data)
    }
}

/// One phone IMU sample: specific force (m/s², gravity included), rotation rate
/// (rad/s), magnetic field (µT, nil without a magnetometer), device axes (the
/// Stridekit `ImuSample` record without the import; `ImuLayout` packs it).
public struct ImuRecord: Equatable, Sendable {
    public var tS: Double
    public var gyroRads: Vector3
    public var accelMps2: Vector3
    public var magUt: Vector3?

    public init(tS: Double, gyroRads: Vector3, accelMps2: Vector3, magUt: Vector3?) {
        self.tS = tS
        self.gyroRads = gyroRads
        self.accelMps2 = accelMps2
        self.magUt = magUt
    }
}

/// The IMU layout family (Rust: `packed.rs`): the 6-axis record, and the 9-axis record
/// = the same 56 bytes followed by the magnetometer. Both carry accel before gyro.
///
/// `FootNavigator.pushPacked`: the 6-axis record, 56 bytes, seven f64: `t_s`, accel
/// x y z (m/s²), gyro x y z (rad/s), sensor axes. Rust: `packed::IMU6_RECORD_BYTES`.
public enum FootImuLayout {
    public static let recordBytes = 56
    public static let fields = ["t_s", "accel_x_mps2", "accel_y_mps2", "accel_z_mps2",
                                "gyro_x_rads", "gyro_y_rads", "gyro_z_rads"]

    public static func append(tS: Double, accelMps2 a: Vector3, gyroRads g: Vector3,
                              to data: inout Data) {
        appendLittleEndian(tS, to: &data)
        appendLittleEndian(a.x, to: &data)
        appendLittleEndian(a.y, to: &data)
        appendLittleEndian(a.z, to: &data)
        appendLittleEndian(g.x, to: &data)
        appendLittleEndian(g.y, to: &data)
        appendLittleEndian(g.z, to: &data)
    }
}

/// `pushImuPacked` of `PhoneNavigator`, `PhoneOdometry` and `OrientationFilter`: the
/// 9-axis record, 80 bytes, ten f64: the 6-axis record (`t_s`, accel x y z, gyro x y
/// z), then mag x y z (NaN without a magnetometer). Rust: `packed::IMU_RECORD_BYTES`.
public enum ImuLayout {
    public static let recordBytes = 80
    public static let fields = ["t_s", "accel_x_mps2", "accel_y_mps2", "accel_z_mps2",
                                "gyro_x_rads", "gyro_y_rads", "gyro_z_rads",
                                "mag_x_ut", "mag_y_ut", "mag_z_ut"]

    public static func append(_ s: ImuRecord, to data: inout Data) {
        FootImuLayout.append(tS: s.tS, accelMps2: s.accelMps2, gyroRads: s.gyroRads, to: &data)
        let mag = s.magUt ?? Vector3(.nan, .nan, .nan)
        appendLittleEndian(mag.x, to: &data)
        appendLittleEndian(mag.y, to: &data)
        appendLittleEndian(mag.z, to: &data)
    }
}
