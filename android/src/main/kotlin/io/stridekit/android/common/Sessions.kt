package io.stridekit.android.common

import io.stridekit.GnssFix
import io.stridekit.ImuBatchResult
import io.stridekit.NavEstimate
import io.stridekit.NavException
import io.stridekit.NavStep
import io.stridekit.PaceEstimate
import io.stridekit.PaceTracker
import io.stridekit.PhoneNavigator
import kotlinx.coroutines.channels.BufferOverflow
import kotlinx.coroutines.flow.MutableSharedFlow
import kotlinx.coroutines.flow.SharedFlow
import kotlinx.coroutines.flow.asSharedFlow
import java.nio.ByteBuffer
import java.nio.ByteOrder

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

    /**
     * Everything needed to continue after the process is killed (pending samples are
     * pushed first): the tracker's snapshot, the clock and the step counter. Store
     * [SessionState.toBytes] in `onSaveInstanceState`; [restore] continues exactly.
     */
    fun saveState(): SessionState = synchronized(lock) {
        flushLocked()
        SessionState(tracker.snapshot(), clock.state, stepCounter.state)
    }

    companion object {
        /**
         * A session continuing from [state] with a tracker restored from its snapshot
         * (close it yourself). Then `clock.onBoot(StrideSensors.bootEpochMs())`, and
         * `stepCounter.onReboot()` when that reports a reboot.
         */
        @JvmStatic
        fun restore(state: SessionState, stepSource: StepSource = StepSource.STEP_COUNTER, maxBatch: Int = 128): PaceSession =
            PaceSession(
                PaceTracker.restore(state.engine), stepSource, maxBatch, SessionClock(state.clock),
                StepCounter(state.stepCounter ?: StepCounter.State()),
            )
    }

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
 * Pedestrian dead reckoning from Android sensors: batches the separate
 * accelerometer, gyroscope and magnetometer events as they arrive ([SensorEventBatcher],
 * 40-byte records) into `PhoneNavigator.pushSensorEventsPacked`, which merges them by
 * the SDK's one rule (the rule `stridekit pdr` applies to an Android log: one sample
 * per accelerometer event, gyroscope and magnetometer interpolated, late FIFO batches
 * merged exactly; docs/api.md, "Separate sensor events"); pushes location fixes one
 * by one (after the events up to them); publishes the navigator's estimate after each
 * batch and each fix on [estimates] and every step placed on [steps].
 *
 * Same threading and Flow rules as [PaceSession]. A magnetometer is optional. Call
 * [finish] when the sensors stop: samples still waiting for later gyroscope or
 * magnetometer events go in then. [saveState] / [restore] carry the session across
 * the process being killed (`onSaveInstanceState`).
 */
class NavigatorSession(
    val navigator: PhoneNavigator,
    val maxBatch: Int = 128,
    val clock: SessionClock = SessionClock(),
) : SensorSink {
    private val lock = Any()
    private val events = SensorEventBatcher()
    private val fixOrder = Monotonic()
    private val _estimates = estimateFlow<NavEstimate>()
    private val _steps = MutableSharedFlow<NavStep>(extraBufferCapacity = STEP_BUFFER, onBufferOverflow = BufferOverflow.DROP_OLDEST)
    private val _rejections = rejectionFlow()

    val estimates: SharedFlow<NavEstimate> = _estimates.asSharedFlow()

    /**
     * Each step as the navigator places it (time, position after it, length,
     * azimuth): the track. Not replayed to new collectors; a collector more than
     * [STEP_BUFFER] steps behind loses the oldest.
     */
    val steps: SharedFlow<NavStep> = _steps.asSharedFlow()
    val rejections: SharedFlow<Rejection> = _rejections.asSharedFlow()

    /** Events dropped before the navigator because their sensor's time did not increase. */
    val droppedOutOfOrder: Long get() = synchronized(lock) { events.droppedOutOfOrder + fixOrder.dropped }

    override fun onAccelerometer(elapsedNs: Long, x: Float, y: Float, z: Float) =
        add(PackedBuffer.TYPE_ACCELEROMETER, elapsedNs, x, y, z)

    override fun onGyroscope(elapsedNs: Long, x: Float, y: Float, z: Float) =
        add(PackedBuffer.TYPE_GYROSCOPE, elapsedNs, x, y, z)

    override fun onMagneticField(elapsedNs: Long, x: Float, y: Float, z: Float) =
        add(PackedBuffer.TYPE_MAGNETIC_FIELD, elapsedNs, x, y, z)

    private fun add(type: Long, elapsedNs: Long, x: Float, y: Float, z: Float) {
        synchronized(lock) {
            events.add(clock.seconds(elapsedNs), type, x.toDouble(), y.toDouble(), z.toDouble())
            if (events.buffer.size >= maxBatch) pushEvents()
        }
    }

    override fun onLocation(fix: LocationSample) {
        synchronized(lock) {
            val t = clock.seconds(fix.elapsedNs)
            if (!fixOrder.accept(t)) return
            pushEvents()
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

    /** Push the batched events now; returns the estimate after them (null if none). */
    fun flush(): NavEstimate? = synchronized(lock) { pushEvents() }

    /**
     * The sensors stopped: push the batched events, then the samples the merge still
     * holds back for later gyroscope or magnetometer events. Returns the final
     * estimate. Events that come later merge as before.
     */
    fun finish(): NavEstimate? = synchronized(lock) {
        pushEvents()
        publish(navigator.flushSensorEvents())
    }

    /**
     * Everything needed to continue after the process is killed: the batched events
     * are pushed first, then the navigator's snapshot (with the events its merge
     * still waits on) and the clock are taken. Store [SessionState.toBytes] in
     * `onSaveInstanceState` (or a service's persistent state); [restore] continues
     * exactly where this left off.
     */
    fun saveState(): SessionState = synchronized(lock) {
        pushEvents()
        SessionState(navigator.snapshot(), clock.state, null)
    }

    private fun pushEvents(): NavEstimate? {
        if (events.buffer.isEmpty()) return null
        return publish(navigator.pushSensorEventsPacked(events.buffer.drain()))
    }

    private fun publish(r: ImuBatchResult): NavEstimate? {
        for (x in r.rejected) _rejections.tryEmit(Rejection("sensor event", null, x.reason))
        for (s in r.steps) _steps.tryEmit(s)
        r.latest?.let { _estimates.tryEmit(it) }
        return r.latest
    }

    companion object {
        /** Steps [steps] keeps for a slow collector. */
        const val STEP_BUFFER = 1024

        /**
         * A session continuing from [state] (from [saveState]) with a navigator
         * restored from its snapshot (close it yourself, as the original). Call
         * `clock.onBoot(StrideSensors.bootEpochMs())` next: after a reboot it places
         * the new boot's times after the saved ones.
         */
        @JvmStatic
        fun restore(state: SessionState, maxBatch: Int = 128): NavigatorSession =
            NavigatorSession(PhoneNavigator.restore(state.engine), maxBatch, SessionClock(state.clock))
    }
}

/**
 * What a session needs to continue after the process is killed: the engine's
 * snapshot, the session clock and (pace sessions) the step counter. [toBytes] /
 * [fromBytes] give one `ByteArray` for a `Bundle` or a file (little-endian, versioned).
 */
class SessionState(
    val engine: ByteArray,
    val clock: SessionClock.State,
    val stepCounter: StepCounter.State?,
) {
    fun toBytes(): ByteArray {
        val b = ByteBuffer.allocate(HEADER_BYTES + engine.size).order(ByteOrder.LITTLE_ENDIAN)
        b.putInt(MAGIC).putInt(VERSION)
        b.putDouble(clock.offsetS).putLong(clock.bootEpochMs ?: NO_BOOT).putDouble(clock.lastTs).putLong(clock.lastElapsedNs)
        val c = stepCounter
        b.put(if (c == null) 0 else 1).putLong(c?.offset ?: 0L).putLong(c?.lastRaw ?: -1L).putInt(c?.resets ?: 0)
        b.putInt(engine.size).put(engine)
        return b.array()
    }

    companion object {
        private const val MAGIC = 0x53545353 // "SSTS"
        private const val VERSION = 1
        private const val NO_BOOT = Long.MIN_VALUE
        private const val HEADER_BYTES = 4 + 4 + 8 + 8 + 8 + 8 + 1 + 8 + 8 + 4 + 4

        /** Reads [toBytes]; throws IllegalArgumentException on anything else. */
        @JvmStatic
        fun fromBytes(bytes: ByteArray): SessionState {
            require(bytes.size >= HEADER_BYTES) { "session state: ${bytes.size} bytes is too short" }
            val b = ByteBuffer.wrap(bytes).order(ByteOrder.LITTLE_ENDIAN)
            require(b.int == MAGIC) { "not a stridekit session state" }
            require(b.int == VERSION) { "session state of another version" }
            val clock = SessionClock.State(
                offsetS = b.double,
                bootEpochMs = b.long.takeIf { it != NO_BOOT },
                lastTs = b.double,
                lastElapsedNs = b.long,
            )
            val hasCounter = b.get().toInt() == 1
            val counter = StepCounter.State(offset = b.long, lastRaw = b.long, resets = b.int)
            val n = b.int
            require(n == b.remaining()) { "session state: engine snapshot of $n bytes, ${b.remaining()} left" }
            val engine = ByteArray(n).also { b.get(it) }
            return SessionState(engine, clock, counter.takeIf { hasCounter })
        }
    }
}
