import Foundation
import StridekitPacking
import XCTest

final class PackingTests: XCTestCase {
    private func bytes(_ d: Data) -> [UInt8] { [UInt8](d) }

    func testLittleEndianDoubleAndUInt64() {
        var d = Data()
        appendLittleEndian(1.0, to: &d)
        XCTAssertEqual(bytes(d), [0, 0, 0, 0, 0, 0, 0xF0, 0x3F])
        d = Data()
        appendLittleEndian(UInt64(0x0102_0304_0506_0708), to: &d)
        XCTAssertEqual(bytes(d), [8, 7, 6, 5, 4, 3, 2, 1])
    }

    func testRecordSizesMatchFieldLists() {
        XCTAssertEqual(AccelLayout.recordBytes, 32)
        XCTAssertEqual(StepCountLayout.recordBytes, 16)
        XCTAssertEqual(FixLayout.recordBytes, 56)
        XCTAssertEqual(ImuLayout.recordBytes, 80)
        XCTAssertEqual(FootImuLayout.recordBytes, 56)
        for (n, fields) in [(AccelLayout.recordBytes, AccelLayout.fields),
                                (StepCountLayout.recordBytes, StepCountLayout.fields),
                                (FixLayout.recordBytes, FixLayout.fields),
                                (ImuLayout.recordBytes, ImuLayout.fields),
                                (FootImuLayout.recordBytes, FootImuLayout.fields)] {
            XCTAssertEqual(n, 8 * fields.count)
        }
    }

    func testAccelRecord() {
        var d = Data()
        AccelLayout.append(tS: 12.5, specificForceMps2: Vector3(1, -2, 9.75), to: &d)
        XCTAssertEqual(d.count, AccelLayout.recordBytes)
        XCTAssertEqual([0, 8, 16, 24].map { readLittleEndianDouble(d, at: $0) }, [12.5, 1, -2, 9.75])
    }

    func testStepCountRecord() {
        var d = Data()
        StepCountLayout.append(tS: 3.25, steps: 1234, to: &d)
        XCTAssertEqual(d.count, 16)
        XCTAssertEqual(readLittleEndianDouble(d, at: 0), 3.25)
        XCTAssertEqual(Array(d[8..<16]), [0xD2, 0x04, 0, 0, 0, 0, 0, 0])
    }

    func testFixRecordEncodesAbsentOptionalsAsNaN() {
        var d = Data()
        FixLayout.append(FixRecord(tS: 1, latDeg: 50.5, lonDeg: 18.25, horizontalAccuracyM: 4), to: &d)
        XCTAssertEqual(d.count, 56)
        XCTAssertEqual(readLittleEndianDouble(d, at: 0), 1)
        XCTAssertEqual(readLittleEndianDouble(d, at: 8), 50.5)
        XCTAssertEqual(readLittleEndianDouble(d, at: 16), 18.25)
        XCTAssertTrue(readLittleEndianDouble(d, at: 24).isNaN)      // alt_m
        XCTAssertEqual(readLittleEndianDouble(d, at: 32), 4)        // horizontal_accuracy_m
        XCTAssertTrue(readLittleEndianDouble(d, at: 40).isNaN)      // speed_mps
        XCTAssertTrue(readLittleEndianDouble(d, at: 48).isNaN)      // speed_accuracy_mps
    }

    func testImuRecordOrderAndMissingMagnetometer() {
        var d = Data()
        ImuLayout.append(ImuRecord(tS: 2, gyroRads: Vector3(0.1, 0.2, 0.3),
                                   accelMps2: Vector3(1, 2, 3), magUt: nil), to: &d)
        XCTAssertEqual(d.count, 80)
        let v = (0..<10).map { readLittleEndianDouble(d, at: 8 * $0) }
        XCTAssertEqual(Array(v[0..<7]), [2, 1, 2, 3, 0.1, 0.2, 0.3])  // accel before gyro
        XCTAssertTrue(v[7...].allSatisfy { $0.isNaN })
        // One family: the 80-byte record starts with the 56-byte one.
        var six = Data()
        FootImuLayout.append(tS: 2, accelMps2: Vector3(1, 2, 3), gyroRads: Vector3(0.1, 0.2, 0.3), to: &six)
        XCTAssertEqual(d.prefix(FootImuLayout.recordBytes), six)
        XCTAssertEqual(Array(ImuLayout.fields.prefix(FootImuLayout.fields.count)), FootImuLayout.fields)
    }

    func testFootRecordOrder() {
        var d = Data()
        FootImuLayout.append(tS: 5, accelMps2: Vector3(1, 2, 3), gyroRads: Vector3(4, 5, 6), to: &d)
        XCTAssertEqual((0..<7).map { readLittleEndianDouble(d, at: 8 * $0) }, [5, 1, 2, 3, 4, 5, 6])
    }

    func testCoreMotionAccelerationBecomesSpecificForce() {
        // A phone lying face up: CoreMotion reads z = -1 g; stridekit expects +9.80665 m/s².
        let f = CoreMotionUnits.specificForceMps2(fromG: Vector3(0, 0, -1))
        XCTAssertEqual(f, Vector3(0, 0, 9.80665))
    }

    func testBatcherFlushesOnCountAndLatency() {
        var b = RecordBatcher(recordBytes: 16, maxRecords: 3, maxLatencyS: 10)
        XCTAssertNil(b.add(tS: 0) { StepCountLayout.append(tS: 0, steps: 1, to: &$0) })
        XCTAssertNil(b.add(tS: 1) { StepCountLayout.append(tS: 1, steps: 2, to: &$0) })
        XCTAssertEqual(b.add(tS: 2) { StepCountLayout.append(tS: 2, steps: 3, to: &$0) }?.count, 48)
        XCTAssertEqual(b.count, 0)
        XCTAssertNil(b.add(tS: 3) { StepCountLayout.append(tS: 3, steps: 4, to: &$0) })
        XCTAssertEqual(b.add(tS: 13) { StepCountLayout.append(tS: 13, steps: 5, to: &$0) }?.count, 32)
        XCTAssertNil(b.flush())
    }

    func testAlignerHoldsGyroAndDropsStaleMagnetometer() {
        var a = ImuAligner(maxGyroAge: 0.05, maxMagAge: 0.25)
        XCTAssertNil(a.accelerometer(tS: 0.00, specificForceMps2: Vector3(0, 0, 9.8)))  // no gyro yet
        a.gyroscope(tS: 0.01, rads: Vector3(0.1, 0, 0))
        a.magnetometer(tS: 0.01, microtesla: Vector3(20, 0, -40))
        let r = a.accelerometer(tS: 0.02, specificForceMps2: Vector3(0, 0, 9.8))
        XCTAssertEqual(r?.gyroRads, Vector3(0.1, 0, 0))
        XCTAssertEqual(r?.magUt, Vector3(20, 0, -40))
        a.gyroscope(tS: 0.40, rads: Vector3(0.2, 0, 0))
        XCTAssertNil(a.accelerometer(tS: 0.50, specificForceMps2: Vector3(0, 0, 9.8)))  // gyro 0.1 s old
        let fresh = a.accelerometer(tS: 0.41, specificForceMps2: Vector3(0, 0, 9.8))
        XCTAssertNotNil(fresh)
        XCTAssertNil(fresh?.magUt)                                                      // mag 0.4 s old
    }
}

/// A settable pair of clocks: uptime and wall clock, in seconds.
final class FakeClocks: @unchecked Sendable {
    var uptime: TimeInterval
    var wall: Date
    init(uptime: TimeInterval, wall: Date) {
        self.uptime = uptime
        self.wall = wall
    }
    var clock: MonotonicClock {
        MonotonicClock(uptimeNow: { self.uptime }, wallNow: { self.wall })
    }
}

final class ClockTests: XCTestCase {
    let t0 = Date(timeIntervalSince1970: 1_800_000_000)

    func testCoreMotionTimestampsAreUsedAsIs() {
        let c = FakeClocks(uptime: 5000, wall: t0)
        XCTAssertEqual(c.clock.seconds(fromUptime: 4999.25), 4999.25)
    }

    func testDateIsConvertedThroughItsAge() {
        let c = FakeClocks(uptime: 5000, wall: t0)
        XCTAssertEqual(c.clock.seconds(from: t0.addingTimeInterval(-0.75)), 4999.25, accuracy: 1e-9)
        // A wall-clock step (NTP, user) after the event does not move earlier samples'
        // times: they were converted already, and later ones use the new offset.
        c.wall = t0.addingTimeInterval(3600)
        c.uptime = 5001
        XCTAssertEqual(c.clock.seconds(from: c.wall.addingTimeInterval(-0.5)), 5000.5, accuracy: 1e-9)
    }

    func testLocationConversion() {
        let c = FakeClocks(uptime: 100, wall: t0)
        var r = LocationReading(timestamp: t0.addingTimeInterval(-1), latitude: 50.29, longitude: 18.67,
                                altitude: 250, verticalAccuracy: 3, horizontalAccuracy: 5,
                                speed: 3.1, speedAccuracy: 0.4)
        XCTAssertEqual(LocationConversion.fixRecord(r, clock: c.clock),
                       FixRecord(tS: 99, latDeg: 50.29, lonDeg: 18.67, altM: 250,
                                 horizontalAccuracyM: 5, speedMps: 3.1, speedAccuracyMps: 0.4))
        r.verticalAccuracy = -1
        r.speedAccuracy = -1
        let f = LocationConversion.fixRecord(r, clock: c.clock)
        XCTAssertNil(f?.altM)
        XCTAssertNil(f?.speedMps)        // a speed without its accuracy is not used
        XCTAssertNil(f?.speedAccuracyMps)
        r.horizontalAccuracy = -1        // invalid coordinate
        XCTAssertNil(LocationConversion.fixRecord(r, clock: c.clock))
        r.horizontalAccuracy = 5
        r.timestamp = t0.addingTimeInterval(-60)  // a cached location
        XCTAssertNil(LocationConversion.fixRecord(r, clock: c.clock))
    }
}
