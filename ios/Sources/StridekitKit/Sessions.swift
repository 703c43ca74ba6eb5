// The whole wiring an app would otherwise write: sensors -> pipeline -> AsyncStream.
//
//     let session = PaceSession()                 // on the main thread
//     try session.start()
//     for await e in session.estimates {          // one per GNSS fix
//         label.text = "\(e.speedMps) m/s, \(e.distanceM) m, \(e.source)"
//     }
//     session.stop()                              // ends the stream

#if canImport(CoreMotion) && os(iOS)
import CoreLocation
import CoreMotion
import Foundation
import Stridekit
import StridekitPacking

/// Running pace from CoreLocation + CMPedometer (or the raw accelerometer).
public final class PaceSession {
    public enum StepSource {
        /// CMPedometer cumulative counts (low power; updates every few seconds).
        case pedometer
        /// The accelerometer at `rateHz`; stridekit detects the steps.
        case accelerometer(rateHz: Double)
    }

    public let pipeline: PacePipeline
    public var estimates: AsyncStream<PaceEstimate> { pipeline.estimates }
    public var tracker: PaceTracker { pipeline.tracker }

    private let stepSource: StepSource
    private let location: LocationSource
    private let pedometer: PedometerSource
    private let motion: MotionSource

    public init(tracker: PaceTracker = PaceTracker.withDefaults(), stepSource: StepSource = .pedometer,
                motionManager: CMMotionManager = CMMotionManager(), clock: MonotonicClock = .system,
                onProblem: @escaping ProblemHandler = { _ in }) {
        let pipeline = PacePipeline(tracker: tracker, onProblem: onProblem)
        self.pipeline = pipeline
        self.stepSource = stepSource
        location = LocationSource(clock: clock) { pipeline.push(fixes: $0) }
        pedometer = PedometerSource(clock: clock)
        motion = MotionSource(manager: motionManager, clock: clock)
    }

    public func start() throws {
        switch stepSource {
        case .pedometer:
            let pipeline = self.pipeline
            try pedometer.start { t, steps in pipeline.push(stepCount: steps, tS: t) }
        case .accelerometer(let rateHz):
            let pipeline = self.pipeline
            try motion.startAccelerometer(rateHz: rateHz) { t, a in
                pipeline.push(accelTS: t, specificForceMps2: a)
            }
        }
        location.start()
    }

    /// Stops the sensors, pushes what is buffered and ends `estimates`.
    public func stop() {
        location.stop()
        pedometer.stop()
        motion.stop()
        pipeline.finish()
    }
}

/// Where the phone is carried (PlacementClassifier), from the accelerometer.
public final class PlacementSession {
    public let pipeline: PlacementPipeline
    public var estimates: AsyncStream<PlacementEstimate> { pipeline.estimates }

    private let rateHz: Double
    private let motion: MotionSource

    public init(classifier: PlacementClassifier = PlacementClassifier.withDefaults(), rateHz: Double = 50,
                motionManager: CMMotionManager = CMMotionManager(), clock: MonotonicClock = .system,
                onProblem: @escaping ProblemHandler = { _ in }) {
        pipeline = PlacementPipeline(classifier: classifier, onProblem: onProblem)
        self.rateHz = rateHz
        motion = MotionSource(manager: motionManager, clock: clock)
    }

    public func start() throws {
        let pipeline = self.pipeline
        try motion.startAccelerometer(rateHz: rateHz) { t, a in
            pipeline.push(accelTS: t, specificForceMps2: a)
        }
    }

    public func stop() {
        motion.stop()
        pipeline.finish()
    }
}

/// Pedestrian dead reckoning (PhoneNavigator) from the IMU + CoreLocation.
public final class NavigationSession {
    public let pipeline: NavigationPipeline
    public var estimates: AsyncStream<NavEstimate> { pipeline.estimates }

    private let mode: MotionSource.ImuMode
    private let rateHz: Double
    private let location: LocationSource
    private let motion: MotionSource

    public init(navigator: PhoneNavigator = PhoneNavigator.withDefaults(),
                mode: MotionSource.ImuMode = .raw, rateHz: Double = 100,
                motionManager: CMMotionManager = CMMotionManager(), clock: MonotonicClock = .system,
                onProblem: @escaping ProblemHandler = { _ in }) {
        let pipeline = NavigationPipeline(navigator: navigator, onProblem: onProblem)
        self.pipeline = pipeline
        self.mode = mode
        self.rateHz = rateHz
        location = LocationSource(clock: clock) { pipeline.push(fixes: $0) }
        motion = MotionSource(manager: motionManager, clock: clock)
    }

    public func start() throws {
        let pipeline = self.pipeline
        try motion.startImu(mode: mode, rateHz: rateHz) { pipeline.push(imu: $0) }
        location.start()
    }

    public func stop() {
        location.stop()
        motion.stop()
        pipeline.finish()
    }
}
#endif
