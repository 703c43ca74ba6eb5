// Converted samples -> batched packed pushes -> AsyncStream of estimates.
// No CoreMotion / CoreLocation here: the simulated-walk tests drive these pipelines
// directly; the sensor adapters (MotionSources.swift, LocationSource.swift) feed them.
//
// Threading: every method may be called from any thread (one lock per pipeline; the
// stridekit objects are themselves safe to call from several threads). Batches keep
// the time order of each stream; before a GNSS fix is pushed the buffered motion
// samples are pushed, so every estimate sees all steps up to its fix.

import Foundation
import Stridekit
import StridekitPacking

extension GnssFix {
    /// The stridekit record of a converted fix.
    public init(_ r: FixRecord) {
        self.init(tS: r.tS, latDeg: r.latDeg, lonDeg: r.lonDeg, altM: r.altM,
                  horizontalAccuracyM: r.horizontalAccuracyM, speedMps: r.speedMps,
                  speedAccuracyMps: r.speedAccuracyMps)
    }
}

/// A sample a pipeline could not push: the SDK's sentence (rejected samples leave the
/// engine unchanged; the rest of their batch was processed).
public typealias ProblemHandler = @Sendable (String) -> Void

/// `PaceTracker` fed from converted GNSS fixes and step counts or raw accelerometer
/// samples; `estimates` yields one `PaceEstimate` per accepted fix.
public final class PacePipeline: @unchecked Sendable {
    public let tracker: PaceTracker
    /// One estimate per accepted GNSS fix, in time order. Ends after `finish()`.
    public let estimates: AsyncStream<PaceEstimate>

    private let continuation: AsyncStream<PaceEstimate>.Continuation
    private let onProblem: ProblemHandler
    private let lock = NSLock()
    private var accel: RecordBatcher
    private var steps: RecordBatcher

    /// - Parameters:
    ///   - accelBatch: accelerometer records per push (100 Hz: 100 = one push a second).
    ///   - maxLatencyS: longest a buffered motion sample waits, seconds of sample time.
    ///   - buffering: what the stream keeps when nobody iterates fast enough.
    public init(tracker: PaceTracker = PaceTracker.withDefaults(),
                accelBatch: Int = 100, maxLatencyS: Double = 1.0,
                buffering: AsyncStream<PaceEstimate>.Continuation.BufferingPolicy = .bufferingNewest(256),
                onProblem: @escaping ProblemHandler = { _ in }) {
        self.tracker = tracker
        self.onProblem = onProblem
        var cont: AsyncStream<PaceEstimate>.Continuation?
        estimates = AsyncStream(PaceEstimate.self, bufferingPolicy: buffering) { cont = $0 }
        continuation = cont!
        accel = RecordBatcher(recordBytes: AccelLayout.recordBytes, maxRecords: accelBatch,
                              maxLatencyS: maxLatencyS)
        steps = RecordBatcher(recordBytes: StepCountLayout.recordBytes, maxRecords: 32,
                              maxLatencyS: maxLatencyS)
    }

    /// GNSS fixes (one CoreLocation delivery), in time order.
    public func push(fixes: [FixRecord]) {
        guard !fixes.isEmpty else { return }
        var data = Data(capacity: fixes.count * FixLayout.recordBytes)
        for f in fixes { FixLayout.append(f, to: &data) }
        lock.lock()
        defer { lock.unlock() }
        flushMotionLocked()
        run { try self.tracker.pushFixesPacked(data: data) }
    }

    /// A cumulative step count (CMPedometerData.numberOfSteps since the start date).
    public func push(stepCount steps: Int64, tS: Double) {
        lock.lock()
        defer { lock.unlock() }
        if let batch = self.steps.add(tS: tS, { StepCountLayout.append(tS: tS, steps: steps, to: &$0) }) {
            run { try self.tracker.pushStepCountsPacked(data: batch) }
        }
    }

    /// A raw accelerometer sample as specific force (m/s², gravity included): the
    /// tracker detects steps itself. Use either this or `push(stepCount:tS:)`.
    public func push(accelTS tS: Double, specificForceMps2 a: Vector3) {
        lock.lock()
        defer { lock.unlock() }
        if let batch = accel.add(tS: tS, { AccelLayout.append(tS: tS, specificForceMps2: a, to: &$0) }) {
            run { try self.tracker.pushAccelPacked(data: batch) }
        }
    }

    /// Pushes everything buffered.
    public func flush() {
        lock.lock()
        defer { lock.unlock() }
        flushMotionLocked()
    }

    /// Flushes and ends `estimates`.
    public func finish() {
        flush()
        continuation.finish()
    }

    private func flushMotionLocked() {
        if let batch = steps.flush() {
            run { try self.tracker.pushStepCountsPacked(data: batch) }
        }
        if let batch = accel.flush() {
            run { try self.tracker.pushAccelPacked(data: batch) }
        }
    }

    private func run(_ push: () throws -> BatchResult) {
        do {
            let result = try push()
            for e in result.estimates { continuation.yield(e) }
            for r in result.rejected { onProblem("sample \(r.index): \(r.reason)") }
        } catch {
            // Only a malformed buffer (a bug here) or an internal error of the SDK.
            onProblem("batch not pushed: \(error)")
        }
    }
}

/// `PhoneNavigator` (pedestrian dead reckoning) fed from converted IMU records and GNSS
/// fixes; `estimates` yields the latest `NavEstimate` after every IMU batch and fix.
public final class NavigationPipeline: @unchecked Sendable {
    public let navigator: PhoneNavigator
    public let estimates: AsyncStream<NavEstimate>

    private let continuation: AsyncStream<NavEstimate>.Continuation
    private let onProblem: ProblemHandler
    private let lock = NSLock()
    private var imu: RecordBatcher

    public init(navigator: PhoneNavigator = PhoneNavigator.withDefaults(),
                imuBatch: Int = 100, maxLatencyS: Double = 1.0,
                buffering: AsyncStream<NavEstimate>.Continuation.BufferingPolicy = .bufferingNewest(64),
                onProblem: @escaping ProblemHandler = { _ in }) {
        self.navigator = navigator
        self.onProblem = onProblem
        var cont: AsyncStream<NavEstimate>.Continuation?
        estimates = AsyncStream(NavEstimate.self, bufferingPolicy: buffering) { cont = $0 }
        continuation = cont!
        imu = RecordBatcher(recordBytes: ImuLayout.recordBytes, maxRecords: imuBatch,
                            maxLatencyS: maxLatencyS)
    }

    public func push(imu record: ImuRecord) {
        lock.lock()
        defer { lock.unlock() }
        if let batch = imu.add(tS: record.tS, { ImuLayout.append(record, to: &$0) }) {
            pushImuLocked(batch)
        }
    }

    public func push(fixes: [FixRecord]) {
        lock.lock()
        defer { lock.unlock() }
        if let batch = imu.flush() { pushImuLocked(batch) }
        for f in fixes {
            do {
                let estimate = try navigator.pushFix(fix: GnssFix(f))
                continuation.yield(estimate)
            } catch {
                onProblem("fix at t = \(f.tS) s: \(error)")
            }
        }
    }

    public func flush() {
        lock.lock()
        defer { lock.unlock() }
        if let batch = imu.flush() { pushImuLocked(batch) }
    }

    public func finish() {
        flush()
        continuation.finish()
    }

    private func pushImuLocked(_ batch: Data) {
        do {
            let result = try navigator.pushImuPacked(data: batch)
            for r in result.rejected { onProblem("IMU sample \(r.index): \(r.reason)") }
            if let latest = result.latest { continuation.yield(latest) }
        } catch {
            onProblem("IMU batch not pushed: \(error)")
        }
    }
}

/// `PlacementClassifier` (where the phone is carried) fed from accelerometer samples
/// (the same 32-byte records as the pace tracker); `estimates` yields the latest
/// `PlacementEstimate` after every batch that completed a window.
public final class PlacementPipeline: @unchecked Sendable {
    public let classifier: PlacementClassifier
    public let estimates: AsyncStream<PlacementEstimate>

    private let continuation: AsyncStream<PlacementEstimate>.Continuation
    private let onProblem: ProblemHandler
    private let lock = NSLock()
    private var accel: RecordBatcher

    public init(classifier: PlacementClassifier = PlacementClassifier.withDefaults(),
                accelBatch: Int = 100, maxLatencyS: Double = 1.0,
                buffering: AsyncStream<PlacementEstimate>.Continuation.BufferingPolicy = .bufferingNewest(16),
                onProblem: @escaping ProblemHandler = { _ in }) {
        self.classifier = classifier
        self.onProblem = onProblem
        var cont: AsyncStream<PlacementEstimate>.Continuation?
        estimates = AsyncStream(PlacementEstimate.self, bufferingPolicy: buffering) { cont = $0 }
        continuation = cont!
        accel = RecordBatcher(recordBytes: AccelLayout.recordBytes, maxRecords: accelBatch,
                              maxLatencyS: maxLatencyS)
    }

    public func push(accelTS tS: Double, specificForceMps2 a: Vector3) {
        lock.lock()
        defer { lock.unlock() }
        if let batch = accel.add(tS: tS, { AccelLayout.append(tS: tS, specificForceMps2: a, to: &$0) }) {
            pushLocked(batch)
        }
    }

    public func finish() {
        lock.lock()
        if let batch = accel.flush() { pushLocked(batch) }
        lock.unlock()
        continuation.finish()
    }

    private func pushLocked(_ batch: Data) {
        do {
            let result = try classifier.pushAccelPacked(data: batch)
            for r in result.rejected { onProblem("accelerometer sample \(r.index): \(r.reason)") }
            if result.produced > 0, let latest = result.latest { continuation.yield(latest) }
        } catch {
            onProblem("accelerometer batch not pushed: \(error)")
        }
    }
}
