package io.stridekit.android.common

import io.stridekit.GnssFix
import io.stridekit.NavEstimate
import io.stridekit.NavException
import io.stridekit.PaceEstimate
import io.stridekit.PaceTracker
import io.stridekit.PhoneNavigator
import kotlinx.coroutines.channels.BufferOverflow
import kotlinx.coroutines.flow.MutableSharedFlow
import kotlinx.coroutines.flow.SharedFlow
import kotlinx.coroutines.flow.asSharedFlow

/**
 * What the Android glue (SensorEventListener, LocationListener) calls: raw platform
 * values, timestamps as elapsedRealtime nanoseconds. Implementations are thread-safe:
 * sensor and location callbacks may arrive on different threads.
 */
interface SensorSink {
    /** TYPE_ACCELEROMETER: m/s², gravity included, device axes. */
    fun onAccelerometer(elapsedNs: Long, x: Float, y: Float, z: Float) {}

    /** TYPE_GYROSCOPE: rad/s, device axes. */
    fun onGyroscope(elapsedNs: Long, x: Float, y: Float, z: Float) {}

    /** TYPE_MAGNETIC_FIELD: µT, device axes. */
    fun onMagneticField(elapsedNs: Long, x: Float, y: Float, z: Float) {}

    /** TYPE_STEP_COUNTER: `values[0]`, steps since boot. */
    fun onStepCounter(elapsedNs: Long, stepsSinceBoot: Float) {}

    /** A location update. */
    fun onLocation(fix: LocationSample) {}
}

/** A sample an engine rejected (the rest of its batch was processed). */
data class Rejection(val stream: String, val tS: Double?, val reason: String)

private fun <T> estimateFlow() =
    MutableSharedFlow<T>(replay = 1, extraBufferCapacity = 64, onBufferOverflow = BufferOverflow.DROP_OLDEST)

private fun rejectionFlow() =
    MutableSharedFlow<Rejection>(extraBufferCapacity = 64, onBufferOverflow = BufferOverflow.DROP_OLDEST)

/**
 * Running pace from Android sensors: batches step-counter (or accelerometer) samples
 * and location fixes into the packed pushes of a [PaceTracker], and publishes one
 * [PaceEstimate] per accepted fix on [estimates].
 *
 * Step data is pushed before every fix (so the estimate at a fix has the steps up to
 * it) and whenever [maxBatch] samples are waiting. The tracker is not owned: close it
 * yourself. All methods may be called from any thread; pushes are serialised in
 * arrival order under one lock (the tracker itself is locked too).
 *
 * [estimates] replays the newest estimate to new collectors and never blocks the
 * sensor thread: a slow collector loses the oldest of more than 64 pending estimates.
 */
class PaceSession(
    val tracker: PaceTracker,
    val stepSource: StepSource = StepSource.STEP_COUNTER,
    val maxBatch: Int = 128,
    val clock: SessionClock = SessionClock(),
    val stepCounter: StepCounter = StepCounter(),
) : SensorSink {
    /** Which platform stream feeds the tracker's step input (one per tracker). */
    enum class StepSource { STEP_COUNTER, ACCELEROMETER }

    private val lock = Any()
    private val steps = StepCountBatcher()
    private val accel = AccelBatcher()
    private val fixes = FixBatcher()
    private val _estimates = estimateFlow<PaceEstimate>()
    private val _rejections = rejectionFlow()

    val estimates: SharedFlow<PaceEstimate> = _estimates.asSharedFlow()
    val rejections: SharedFlow<Rejection> = _rejections.asSharedFlow()

    /** Samples dropped before the tracker because their time did not increase. */
    val droppedOutOfOrder: Long get() = synchronized(lock) { steps.order.dropped + accel.order.dropped + fixes.order.dropped }

    override fun onAccelerometer(elapsedNs: Long, x: Float, y: Float, z: Float) {
        if (stepSource != StepSource.ACCELEROMETER) return
        synchronized(lock) {
            accel.add(clock.seconds(elapsedNs), x.toDouble(), y.toDouble(), z.toDouble())
            if (accel.buffer.size >= maxBatch) pushSteps()
        }
    }

    override fun onStepCounter(elapsedNs: Long, stepsSinceBoot: Float) {
        if (stepSource != StepSource.STEP_COUNTER) return
        synchronized(lock) {
            val total = stepCounter.onReport(stepsSinceBoot)
            steps.add(clock.seconds(elapsedNs), total)
            if (steps.buffer.size >= maxBatch) pushSteps()
        }
    }

    override fun onLocation(fix: LocationSample) {
        synchronized(lock) {
            if (fixes.add(clock.seconds(fix.elapsedNs), fix)) flushLocked()
        }
    }

    /** Push everything pending now; returns the estimates of the pushed fixes. */
    fun flush(): List<PaceEstimate> = synchronized(lock) { flushLocked() }

    private fun flushLocked(): List<PaceEstimate> {
        pushSteps()
        if (fixes.buffer.isEmpty()) return emptyList()
        val r = tracker.pushFixesPacked(fixes.buffer.drain())
        for (x in r.rejected) _rejections.tryEmit(Rejection("gnss", null, x.reason))
        for (e in r.estimates) _estimates.tryEmit(e)
        return r.estimates
    }

    private fun pushSteps() {
        if (!steps.buffer.isEmpty()) {
            val r = tracker.pushStepCountsPacked(steps.buffer.drain())
            for (x in r.rejected) _rejections.tryEmit(Rejection("steps", null, x.reason))
        }
        if (!accel.buffer.isEmpty()) {
            val r = tracker.pushAccelPacked(accel.buffer.drain())
            for (x in r.rejected) _rejections.tryEmit(Rejection("accelerometer", null, x.reason))
        }
    }
}

/**
 * Pedestrian dead reckoning from Android sensors: merges accelerometer, gyroscope and
 * magnetometer events into packed IMU records ([ImuMerger]) for a [PhoneNavigator],
 * pushes location fixes one by one (after the IMU data up to them), and publishes the
 * navigator's estimate after each IMU batch and each fix on [estimates].
 *
 * Same threading and Flow rules as [PaceSession]. A magnetometer is optional (NaN
 * when none, or when its newest sample is older than [ImuMerger.maxMagAgeS]).
 */
class NavigatorSession(
    val navigator: PhoneNavigator,
    val maxBatch: Int = 128,
    val clock: SessionClock = SessionClock(),
    val merger: ImuMerger = ImuMerger(),
) : SensorSink {
    private val lock = Any()
    private val fixOrder = Monotonic()
    private val _estimates = estimateFlow<NavEstimate>()
    private val _rejections = rejectionFlow()

    val estimates: SharedFlow<NavEstimate> = _estimates.asSharedFlow()
    val rejections: SharedFlow<Rejection> = _rejections.asSharedFlow()

    override fun onAccelerometer(elapsedNs: Long, x: Float, y: Float, z: Float) {
        synchronized(lock) {
            merger.onAccel(clock.seconds(elapsedNs), x.toDouble(), y.toDouble(), z.toDouble())
            if (merger.buffer.size >= maxBatch) pushImu()
        }
    }

    override fun onGyroscope(elapsedNs: Long, x: Float, y: Float, z: Float) {
        synchronized(lock) { merger.onGyro(clock.seconds(elapsedNs), x.toDouble(), y.toDouble(), z.toDouble()) }
    }

    override fun onMagneticField(elapsedNs: Long, x: Float, y: Float, z: Float) {
        synchronized(lock) { merger.onMag(clock.seconds(elapsedNs), x.toDouble(), y.toDouble(), z.toDouble()) }
    }

    override fun onLocation(fix: LocationSample) {
        synchronized(lock) {
            val t = clock.seconds(fix.elapsedNs)
            if (!fixOrder.accept(t)) return
            pushImu()
            try {
                val e = navigator.pushFix(
                    GnssFix(tS = t, latDeg = fix.latDeg, lonDeg = fix.lonDeg, altM = fix.altM,
                        horizontalAccuracyM = fix.horizontalAccuracyM, speedMps = fix.speedMps,
                        speedAccuracyMps = fix.speedAccuracyMps),
                )
                _estimates.tryEmit(e)
            } catch (e: NavException) {
                _rejections.tryEmit(Rejection("gnss", t, e.toString()))
            }
        }
    }

    /** Push the pending IMU records now; returns the estimate after them (null if none). */
    fun flush(): NavEstimate? = synchronized(lock) { pushImu() }

    private fun pushImu(): NavEstimate? {
        if (merger.buffer.isEmpty()) return null
        val r = navigator.pushImuPacked(merger.buffer.drain())
        for (x in r.rejected) _rejections.tryEmit(Rejection("imu", null, x.reason))
        r.latest?.let { _estimates.tryEmit(it) }
        return r.latest
    }
}
