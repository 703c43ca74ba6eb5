package io.stridekit.tests

import io.stridekit.GnssFix
import io.stridekit.NavEstimate
import io.stridekit.PaceEstimate
import io.stridekit.PaceSample
import io.stridekit.PaceTracker
import io.stridekit.PhoneNavigator
import io.stridekit.StepSample
import io.stridekit.android.common.AccelBatcher
import io.stridekit.android.common.FixBatcher
import io.stridekit.android.common.LocationSample
import io.stridekit.android.common.NavigatorSession
import io.stridekit.android.common.PaceSession
import io.stridekit.android.common.PackedBuffer
import io.stridekit.android.common.SensorClock
import io.stridekit.android.common.SensorEventBatcher
import io.stridekit.android.common.StepCountBatcher
import io.stridekit.ImuEvent
import io.stridekit.packImuEvents
import kotlinx.coroutines.CompletableDeferred
import kotlinx.coroutines.Dispatchers
import kotlinx.coroutines.channels.Channel
import kotlinx.coroutines.flow.first
import kotlinx.coroutines.flow.onSubscription
import kotlinx.coroutines.launch
import kotlinx.coroutines.runBlocking
import kotlinx.coroutines.withTimeout
import java.nio.ByteBuffer
import java.nio.ByteOrder
import kotlin.math.PI
import kotlin.math.roundToLong
import kotlin.math.sin
import kotlin.test.Test
import kotlin.test.assertContentEquals
import kotlin.test.assertEquals
import kotlin.test.assertFailsWith
import kotlin.test.assertTrue

/** The Android adapters' packing, merging and Flow against the real native objects. */
class AndroidAdaptersTest {
    private val boot = 123L * 86_400L * SensorClock.NANOS_PER_SECOND // 123 days of uptime: beyond 2^53 ns

    private fun ns(tS: Double): Long = boot + (tS * 1e9).roundToLong()

    private fun location(f: GnssFix) = LocationSample(
        elapsedNs = ns(f.tS), latDeg = f.latDeg, lonDeg = f.lonDeg, altM = f.altM,
        horizontalAccuracyM = f.horizontalAccuracyM, speedMps = f.speedMps, speedAccuracyMps = f.speedAccuracyMps,
    )

    @Test
    fun `batchers write the documented layouts`() {
        val fixes = Sim.run.fixes.take(300)
        val fb = FixBatcher()
        for (f in fixes) assertTrue(fb.add(f.tS, location(f)))
        assertEquals(300, fb.buffer.size)
        assertContentEquals(KotlinPacking.fixes(fixes), fb.buffer.drain())
        assertTrue(fb.buffer.isEmpty())

        val counts = Sim.run.steps.take(500).map { it as StepSample.Count }
        val sb = StepCountBatcher()
        for (c in counts) sb.add(c.tS, c.steps.toLong())
        assertContentEquals(KotlinPacking.stepCounts(counts), sb.buffer.drain())

        val ab = AccelBatcher()
        assertTrue(ab.add(1.0, 0.1, 0.2, 9.8))
        assertTrue(!ab.add(1.0, 0.0, 0.0, 0.0) && !ab.add(0.5, 0.0, 0.0, 0.0), "times must increase")
        assertEquals(2, ab.order.dropped)
        val b = ByteBuffer.wrap(ab.buffer.drain()).order(ByteOrder.LITTLE_ENDIAN)
        assertEquals(listOf(1.0, 0.1, 0.2, 9.8), List(4) { b.getDouble() })
        assertEquals(0, b.remaining())

        // Growth beyond the initial capacity, and incomplete records are refused.
        val p = PackedBuffer(16, initialRecords = 1)
        repeat(1000) { p.begin().f64(it.toDouble()).u64(it.toLong()).end() }
        val out = ByteBuffer.wrap(p.drain()).order(ByteOrder.LITTLE_ENDIAN)
        assertEquals(16_000, out.capacity())
        out.position(16 * 999)
        assertEquals(999.0, out.getDouble())
        assertFailsWith<IllegalStateException> { p.begin().f64(1.0).end() }

        // The packed pushes give the same estimates as the record-list API.
        PaceTracker.withDefaults().use { a ->
            PaceTracker.withDefaults().use { b2 ->
                val fb2 = FixBatcher()
                fixes.forEach { fb2.add(it.tS, location(it)) }
                assertBitIdentical(a.pushFixes(fixes).estimates, b2.pushFixesPacked(fb2.buffer.drain()).estimates, "packed fixes")
            }
        }
    }

    @Test
    fun `the sensor-event batcher writes the 40-byte layout and drops what goes back in time`() {
        val b = SensorEventBatcher()
        assertTrue(b.add(0.01, PackedBuffer.TYPE_ACCELEROMETER, 1.0, 2.0, 9.8))
        assertTrue(b.add(0.004, PackedBuffer.TYPE_GYROSCOPE, 0.1, 0.2, 0.3))
        assertTrue(b.add(0.012, PackedBuffer.TYPE_MAGNETIC_FIELD, 20.0, 0.0, -40.0))
        assertTrue(!b.add(0.01, PackedBuffer.TYPE_ACCELEROMETER, 1.0, 2.0, 9.8), "repeated time")
        assertEquals(1L, b.droppedOutOfOrder)
        assertFailsWith<IllegalArgumentException> { b.add(0.02, 5L, 0.0, 0.0, 0.0) }
        val bytes = b.buffer.drain()
        // The Rust pack helper writes the same bytes.
        assertContentEquals(
            packImuEvents(listOf(
                ImuEvent(0.01, 1, 1.0, 2.0, 9.8), ImuEvent(0.004, 4, 0.1, 0.2, 0.3), ImuEvent(0.012, 2, 20.0, 0.0, -40.0),
            )),
            bytes,
        )
        val r = ByteBuffer.wrap(bytes).order(ByteOrder.LITTLE_ENDIAN)
        assertEquals(0.01, r.getDouble())
        assertEquals(1L, r.getLong())
    }

    /** The simulated run as Android delivers it: step-counter Floats and locations, in time order. */
    private fun replay(session: PaceSession, samples: List<PaceSample>, each: (PaceSample) -> Unit = {}) {
        for (s in samples) {
            when (s) {
                is PaceSample.Fix -> session.onLocation(location(s.fix))
                is PaceSample.Steps -> {
                    val c = s.sample as StepSample.Count
                    session.onStepCounter(ns(c.tS), c.steps.toFloat())
                }
            }
            each(s)
        }
    }

    /** What the session must produce: the same samples, times converted, pushed by hand. */
    private fun reference(samples: List<PaceSample>): List<PaceEstimate> = PaceTracker.withDefaults().use { t ->
        val conv = samples.map { s ->
            when (s) {
                is PaceSample.Fix -> PaceSample.Fix(s.fix.copy(tS = SensorClock.nanosToSeconds(ns(s.fix.tS))))
                is PaceSample.Steps -> {
                    val c = s.sample as StepSample.Count
                    PaceSample.Steps(StepSample.Count(tS = SensorClock.nanosToSeconds(ns(c.tS)), steps = c.steps))
                }
            }
        }
        conv.chunked(500).flatMap { t.pushSamples(it).estimates }
    }

    @Test
    fun `a pace session streams the tracker's estimates as a Flow`() = runBlocking {
        val samples = Sim.run.samples
        val expected = reference(samples)
        assertTrue(expected.size > 500)
        PaceTracker.withDefaults().use { tracker ->
            val session = PaceSession(tracker, maxBatch = 32)
            val received = Channel<PaceEstimate>(Channel.UNLIMITED)
            val subscribed = CompletableDeferred<Unit>()
            val job = launch(Dispatchers.Default) {
                session.estimates.onSubscription { subscribed.complete(Unit) }.collect { received.send(it) }
            }
            // Wait until the collector is subscribed, then feed sample by sample and
            // take each fix's estimate off the Flow before going on.
            withTimeout(10_000) { subscribed.await() }
            val got = mutableListOf<PaceEstimate>()
            replay(session, samples) { s ->
                if (s is PaceSample.Fix) runBlocking { withTimeout(10_000) { got.add(received.receive()) } }
            }
            job.cancel()
            assertBitIdentical(expected, got, "session Flow vs hand-pushed tracker")
            // A new collector gets the newest estimate at once (replay = 1).
            assertEquals(expected.last().bits(), withTimeout(5_000) { session.estimates.first() }.bits())
            assertEquals(0L, session.droppedOutOfOrder)
        }
    }

    @Test
    fun `a session's flush returns the same estimates as the Flow`() {
        val samples = Sim.run.samples.take(2_000)
        PaceTracker.withDefaults().use { tracker ->
            val session = PaceSession(tracker, maxBatch = 1_000_000)
            val got = mutableListOf<PaceEstimate>()
            for (s in samples) {
                if (s is PaceSample.Fix) {
                    session.onLocation(location(s.fix).copy(elapsedNs = ns(s.fix.tS)))
                } else {
                    val c = (s as PaceSample.Steps).sample as StepSample.Count
                    session.onStepCounter(ns(c.tS), c.steps.toFloat())
                }
            }
            got += session.flush()
            assertTrue(got.isEmpty(), "fixes are pushed as they arrive: nothing left")
            assertEquals(reference(samples).last().bits(), tracker.estimate()!!.bits())
        }
    }

    @Test
    fun `a navigator session merges separate sensor events and publishes estimates`() = runBlocking {
        PhoneNavigator.withDefaults().use { nav ->
            val session = NavigatorSession(nav, maxBatch = 50)
            val all = Channel<NavEstimate>(Channel.UNLIMITED)
            val subscribed = CompletableDeferred<Unit>()
            val job = launch(Dispatchers.Default) {
                session.estimates.onSubscription { subscribed.complete(Unit) }.collect { all.send(it) }
            }
            withTimeout(10_000) { subscribed.await() }
            // 100 Hz accelerometer, gyroscope 3 ms later, magnetometer at 50 Hz; a walk
            // after 5 s at rest; a fix every second.
            for (i in 0 until 3_000) {
                val t = i / 100.0
                val bounce = if (t > 5.0) 2.5 * sin(2 * PI * 1.8 * t) else 0.0
                session.onGyroscope(ns(t - 0.003), 0f, 0f, 0f)
                if (i % 2 == 0) session.onMagneticField(ns(t - 0.001), 20f, 0f, -40f)
                session.onAccelerometer(ns(t), 0f, (0.3 * bounce).toFloat(), (9.81 + bounce).toFloat())
                if (i % 100 == 99) {
                    session.onLocation(LocationSample(ns(t + 0.005), 46.5 + t * 1e-5, 6.6, horizontalAccuracyM = 5.0))
                }
            }
            session.finish()
            val last = withTimeout(5_000) { session.estimates.first() }
            // Wait until the collector has seen the final estimate (it runs on another
            // thread and may lag on a loaded machine), then take what it received.
            val received = mutableListOf<NavEstimate>()
            withTimeout(30_000) {
                while (received.lastOrNull() != last) received.add(all.receive())
            }
            job.cancel()
            generateSequence { all.tryReceive().getOrNull() }.toCollection(received)
            // One estimate per 50-event batch (7 500 events) and per fix, and one at the
            // end: at most 181. The flow drops the oldest beyond its buffer of 64 when the
            // collector falls behind, so how many arrive depends on the machine's load;
            // the newest always does.
            assertTrue(received.size in 1..181, "estimates received: ${received.size}")
            assertEquals(last, received.last())
            assertTrue(last.steps > 20L, "steps detected: ${last.steps}")
            assertEquals(nav.estimate(), last)
            val counts = nav.sensorEventCounts()
            assertEquals(0L, counts.withoutGyro)
            assertEquals(3_000L, counts.samples)
            assertEquals(0L, session.droppedOutOfOrder)
        }
    }
}
