// Through the real bindings (the XCFramework): the Swift packers and pipelines must
// give exactly what Rust computes from the same simulated data.

import Foundation
import Stridekit
import StridekitKit
import StridekitPacking
import XCTest

final class SimulatedWalkTests: XCTestCase {
    private func record(_ f: GnssFix) -> FixRecord {
        FixRecord(tS: f.tS, latDeg: f.latDeg, lonDeg: f.lonDeg, altM: f.altM,
                  horizontalAccuracyM: f.horizontalAccuracyM, speedMps: f.speedMps,
                  speedAccuracyMps: f.speedAccuracyMps)
    }

    func testSwiftPackingIsByteIdenticalToRust() throws {
        let run = try simulateRun(seed: 3, durationS: 120)
        var fixes = Data()
        for f in run.fixes { FixLayout.append(record(f), to: &fixes) }
        XCTAssertEqual(fixes, packFixes(fixes: run.fixes))

        var counts = Data()
        for s in run.steps {
            guard case let .count(tS, steps) = s else { return XCTFail("expected step counts") }
            StepCountLayout.append(tS: tS, steps: steps, to: &counts)
        }
        XCTAssertEqual(counts, packStepCounts(samples: run.steps))

        // One ImuSample record for both IMU layouts (the foot one ignores the magnetometer).
        let samples = [ImuSample(tS: 0.005, accelXMps2: 0.1, accelYMps2: -0.2, accelZMps2: 9.8,
                                 gyroXRads: 0.01, gyroYRads: 0.02, gyroZRads: -0.03,
                                 magXUt: 20, magYUt: 0, magZUt: -40),
                       ImuSample(tS: 0.010, accelXMps2: 0.2, accelYMps2: -0.1, accelZMps2: 9.7,
                                 gyroXRads: 0.02, gyroYRads: 0.01, gyroZRads: -0.02)]
        var foot = Data()
        var imu = Data()
        for s in samples {
            let accel = Vector3(s.accelXMps2, s.accelYMps2, s.accelZMps2)
            let gyro = Vector3(s.gyroXRads, s.gyroYRads, s.gyroZRads)
            FootImuLayout.append(tS: s.tS, accelMps2: accel, gyroRads: gyro, to: &foot)
            var mag: Vector3? = nil
            if let x = s.magXUt, let y = s.magYUt, let z = s.magZUt { mag = Vector3(x, y, z) }
            ImuLayout.append(ImuRecord(tS: s.tS, gyroRads: gyro, accelMps2: accel, magUt: mag), to: &imu)
        }
        XCTAssertEqual(foot, packFootSamples(samples: samples))
        XCTAssertEqual(imu, packImuSamples(samples: samples))
    }

    /// A 10-minute simulated run pushed through PacePipeline (packed batches, the
    /// AsyncStream) gives Rust's reference estimates exactly.
    func testSimulatedRunThroughThePipelineMatchesRust() async throws {
        let run = try simulateRun(seed: 7, durationS: 600)
        XCTAssertEqual(run.referenceRejected, 0)
        let problems = ProblemLog()
        let pipeline = PacePipeline(buffering: .unbounded, onProblem: { problems.add($0) })
        for s in run.samples {
            switch s {
            case .fix(let f):
                pipeline.push(fixes: [record(f)])
            case .steps(.count(let tS, let steps)):
                pipeline.push(stepCount: steps, tS: tS)
            case .steps:
                XCTFail("the simulator reports cumulative counts")
            }
        }
        pipeline.finish()
        var estimates: [PaceEstimate] = []
        for await e in pipeline.estimates { estimates.append(e) }
        XCTAssertEqual(problems.all, [])
        XCTAssertEqual(estimates.count, run.referenceEstimates.count)
        XCTAssertEqual(estimates, run.referenceEstimates)
        XCTAssertEqual(pipeline.tracker.estimate(), run.referenceFinal)
    }

    /// The simulated foot walk, re-packed by the Swift packer, gives Rust's reference.
    func testSimulatedFootWalkRepackedMatchesRust() throws {
        let walk = try simulateFootWalk(seed: 1, laps: 2)
        let data = walk.samplesPacked
        XCTAssertEqual(data.count, Int(walk.sampleCount) * FootImuLayout.recordBytes)
        var repacked = Data(capacity: data.count)
        for i in 0..<Int(walk.sampleCount) {
            let v = (0..<7).map { readLittleEndianDouble(data, at: i * 56 + 8 * $0) }
            FootImuLayout.append(tS: v[0], accelMps2: Vector3(v[1], v[2], v[3]),
                                 gyroRads: Vector3(v[4], v[5], v[6]), to: &repacked)
        }
        XCTAssertEqual(repacked, data)
        let nav = FootNavigator.withDefaults()
        let result = try nav.pushPacked(data: repacked, output: .latestOnly)
        XCTAssertEqual(result.rejected.count, 0)
        XCTAssertEqual(nav.estimate(), walk.referenceFinal)
    }

    func testAccelAndImuBuffersAreAccepted() throws {
        // 4 s at 100 Hz of a phone lying still, face up, through the CoreMotion unit rule.
        let still = CoreMotionUnits.specificForceMps2(fromG: Vector3(0, 0, -1))
        var accel = Data()
        var imu = Data()
        for i in 0..<400 {
            let t = 10 + Double(i) / 100
            AccelLayout.append(tS: t, specificForceMps2: still, to: &accel)
            ImuLayout.append(ImuRecord(tS: t, gyroRads: Vector3(0, 0, 0), accelMps2: still,
                                       magUt: Vector3(20, 0, -40)), to: &imu)
        }
        let tracker = PaceTracker.withDefaults()
        XCTAssertEqual(try tracker.pushAccelPacked(data: accel).rejected.count, 0)
        XCTAssertEqual(tracker.detectedSteps(), 0)
        let nav = PhoneNavigator.withDefaults()
        XCTAssertEqual(try nav.pushImuPacked(data: imu).rejected.count, 0)
        XCTAssertEqual(nav.estimate().steps, 0)

        // A buffer that is not a whole number of records is rejected as a whole, typed.
        XCTAssertThrowsError(try tracker.pushAccelPacked(data: accel.prefix(31))) { error in
            guard case .InvalidBuffer? = error as? PaceError else { return XCTFail("\(error)") }
        }
        XCTAssertThrowsError(try nav.pushImuPacked(data: imu.prefix(79))) { error in
            guard case .InvalidBuffer? = error as? NavError else { return XCTFail("\(error)") }
        }
    }

    /// Packed accelerometer records give the classifier exactly what the record API gives.
    func testPlacementPackedEqualsRecords() async throws {
        var samples: [AccelSample] = []
        for i in 0..<(20 * 50) {  // 20 s at 50 Hz of a swinging, bouncing phone
            let t = 100 + Double(i) / 50
            let s = 2 * Double.pi * 1.8 * t
            samples.append(AccelSample(tS: t, xMps2: 3 * sin(s / 2), yMps2: 9.0 + 2.5 * sin(s),
                                       zMps2: 1.5 * cos(s)))
        }
        let byRecords = PlacementClassifier.withDefaults()
        let r = try byRecords.pushAccelSamples(samples: samples)
        XCTAssertEqual(r.rejected.count, 0)
        let pipeline = PlacementPipeline(accelBatch: 64, buffering: .unbounded)
        for s in samples {
            pipeline.push(accelTS: s.tS, specificForceMps2: Vector3(s.xMps2, s.yMps2, s.zMps2))
        }
        pipeline.finish()
        var last: PlacementEstimate?
        for await e in pipeline.estimates { last = e }
        XCTAssertNotNil(last)
        XCTAssertEqual(pipeline.classifier.estimate(), byRecords.estimate())
        XCTAssertEqual(pipeline.classifier.snapshot(), byRecords.snapshot())
    }

    func testNavigationPipelineStreamsEstimates() async throws {
        let pipeline = NavigationPipeline(imuBatch: 50, buffering: .unbounded)
        let still = CoreMotionUnits.specificForceMps2(fromG: Vector3(0, 0, -1))
        for i in 0..<200 {
            pipeline.push(imu: ImuRecord(tS: Double(i) / 100, gyroRads: Vector3(0, 0, 0),
                                         accelMps2: still, magUt: nil))
        }
        pipeline.push(fixes: [FixRecord(tS: 2.0, latDeg: 50.29, lonDeg: 18.67, horizontalAccuracyM: 5)])
        pipeline.finish()
        var n = 0
        var last: NavEstimate?
        for await e in pipeline.estimates {
            n += 1
            last = e
        }
        XCTAssertEqual(n, 4 + 1)  // four IMU batches of 50, one fix
        XCTAssertEqual(try XCTUnwrap(last?.latDeg), 50.29, accuracy: 1e-6)
    }
}

final class ProblemLog: @unchecked Sendable {
    private let lock = NSLock()
    private var items: [String] = []
    func add(_ s: String) {
        lock.lock()
        items.append(s)
        lock.unlock()
    }
    var all: [String] {
        lock.lock()
        defer { lock.unlock() }
        return items
    }
}
