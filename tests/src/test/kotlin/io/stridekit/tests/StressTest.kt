package io.stridekit.tests

import io.stridekit.FootException
import io.stridekit.FootNavigator
import io.stridekit.FootOutput
import io.stridekit.NavException
import io.stridekit.OdometryException
import io.stridekit.OrientationException
import io.stridekit.OrientationFilter
import io.stridekit.OrientationOutput
import io.stridekit.PaceException
import io.stridekit.PaceTracker
import io.stridekit.PhoneNavigator
import io.stridekit.PhoneOdometry
import io.stridekit.PlacementClassifier
import io.stridekit.PlacementException
import io.stridekit.pdrReferenceReplay
import org.junit.jupiter.api.Test
import java.lang.reflect.Modifier
import java.nio.ByteBuffer
import java.nio.ByteOrder
import java.util.Random
import java.util.concurrent.ConcurrentLinkedQueue
import java.util.concurrent.CountDownLatch
import java.util.concurrent.Executors
import java.util.concurrent.TimeUnit
import java.util.concurrent.atomic.AtomicInteger
import kotlin.math.PI
import kotlin.math.cos
import kotlin.math.sin
import kotlin.test.assertContentEquals
import kotlin.test.assertEquals
import kotlin.test.assertTrue

/**
 * Issue 11, Kotlin stress: 8 threads pushing random packed bytes into every object.
 * Every call returns or throws the object's typed exception (never its `Internal`
 * variant, never uniffi's `InternalException`, never anything untyped); a buffer that
 * is not a whole number of records is refused as a whole with `InvalidBuffer`, a whole
 * buffer is never refused as a whole; returned estimates are finite. Afterwards the
 * same object accepts a realistic sequence and its snapshot restores.
 *
 * Buffers: fully random bytes of random length (mostly not a whole number of records),
 * random bytes of a whole number of records, well-formed records (f64 fields among
 * normal values, NaN, ±∞, 1e300, subnormal, negative, just out of range; times that
 * advance, repeat, go backwards, jump to milli-/nanosecond scale, jump by years or
 * slow intervals) and well-formed buffers truncated or with flipped bytes. Each
 * thread has its own fixed-seed Random; the interleaving of the 8 threads is not
 * reproducible, so a failure prints the seed, the call and the buffer (hex).
 */
class StressTest {
    private companion object {
        const val THREADS = 8
        const val SEED = 20_261_111L
        /** Time of the warm-up sample that anchors every stream before the threads start. */
        const val T0 = 1000.0

        val SPECIALS = doubleArrayOf(
            Double.NaN, Double.POSITIVE_INFINITY, Double.NEGATIVE_INFINITY,
            1e300, -1e300, Double.MAX_VALUE, -Double.MAX_VALUE,
            Double.MIN_VALUE, -Double.MIN_VALUE, 1e-300, 0.0, -0.0,
            -1.0, -1e6, 1e5, 2000.0, 2000.0000001, -2000.0000001, 5000.1, 200.1, 91.0, -181.0,
        )
        val TIME_SPECIALS = doubleArrayOf(
            Double.NaN, Double.POSITIVE_INFINITY, Double.NEGATIVE_INFINITY,
            1e300, -1e300, Double.MAX_VALUE, Double.MIN_VALUE, -Double.MIN_VALUE, 1e-300,
            0.0, -0.0, -1.0, -1e10, 1e11, 1.0000001e11, -1e11, 1.7e12, 1.7e18,
        )
    }

    // ------------------------------------------------------------------------------
    // Times
    // ------------------------------------------------------------------------------

    /**
     * The times of one input stream of one object, shared by the threads: "normal"
     * times advance by the stream's interval from the newest accepted (or issued) time,
     * so that the threads' well-formed records are often accepted. Accepted times are
     * recorded from the rejected indices of each call: accepted times increase, so their
     * maximum is the stream's last accepted time, after which the final valid sequence
     * starts.
     */
    private class StreamClock(start: Double, val dt: Double) {
        private var issued = start
        private var maxAccepted = Double.NEGATIVE_INFINITY

        private fun base(): Double =
            if (maxAccepted == Double.NEGATIVE_INFINITY) issued
            // Issued far ahead of what was accepted (a refused jump): fall back, else
            // every later interval would be "slow" and refused.
            else if (issued - maxAccepted > 50 * dt) maxAccepted
            else maxOf(issued, maxAccepted)

        @Synchronized fun next(): Double = (base() + dt).also { issued = it }
        @Synchronized fun last(): Double = base()
        @Synchronized fun jump(d: Double): Double = (base() + d).also { issued = it }
        @Synchronized fun accepted(t: Double) { if (t > maxAccepted) maxAccepted = t }
        @Synchronized fun maxAccepted(): Double = maxAccepted
    }

    private fun special(r: Random) = SPECIALS[r.nextInt(SPECIALS.size)]

    /** A field: usually `normal`, sometimes a special value or random bits. */
    private fun field(r: Random, normal: Double): Double {
        val p = r.nextInt(100)
        return when {
            p < 10 -> special(r)
            p < 12 -> Double.fromBits(r.nextLong())
            p < 14 -> -normal
            else -> normal
        }
    }

    private fun time(r: Random, c: StreamClock): Double {
        val p = r.nextInt(100)
        return when {
            p < 62 -> c.next()
            p < 67 -> c.last() // duplicate
            p < 72 -> c.last() - r.nextDouble() * 10.0 // backwards
            p < 74 -> c.last() - c.dt * 1e-9 // backwards by a hair
            p < 76 -> (1e5 + c.last()) * 1e9 // nanoseconds since boot
            p < 78 -> 1.7e12 + c.last() * 1e3 // Unix milliseconds
            p < 80 -> c.last() + 1e8 // a jump of years
            p < 83 -> c.jump(1.0 + r.nextDouble() * 4.0) // slow interval
            p < 84 -> c.jump(1e3 + r.nextDouble() * 1e6) // long gap, within a year
            p < 86 -> c.last() + r.nextDouble() * 1e-9 // a hair later
            p < 88 -> Double.fromBits(r.nextLong())
            else -> TIME_SPECIALS[r.nextInt(TIME_SPECIALS.size)]
        }
    }

    // ------------------------------------------------------------------------------
    // Records (layouts: bindings/src/packed.rs)
    // ------------------------------------------------------------------------------

    /** 80-byte IMU record: the 56-byte one (t, accel xyz, gyro xyz), then mag xyz (µT, NaN = none). */
    private fun imuRecord(r: Random, b: ByteBuffer, t: Double) {
        footRecord(r, b, t)
        if (r.nextInt(3) == 0) {
            repeat(3) { b.putDouble(Double.NaN) }
        } else {
            b.putDouble(field(r, 20.0 + r.nextGaussian()))
            b.putDouble(field(r, r.nextGaussian()))
            b.putDouble(field(r, -40.0 + r.nextGaussian()))
        }
    }

    /** 32-byte accelerometer record: t, ax, ay, az (m/s²). */
    private fun accelRecord(r: Random, b: ByteBuffer, t: Double) {
        b.putDouble(t)
        b.putDouble(field(r, r.nextGaussian() * 1.5))
        b.putDouble(field(r, r.nextGaussian() * 1.5))
        b.putDouble(field(r, 9.81 + r.nextGaussian() * 2.0))
    }

    /** 56-byte (6-axis) IMU record, the foot's: t, accel xyz (m/s²), gyro xyz (rad/s). */
    private fun footRecord(r: Random, b: ByteBuffer, t: Double) {
        b.putDouble(t)
        b.putDouble(field(r, r.nextGaussian() * 1.5))
        b.putDouble(field(r, r.nextGaussian() * 1.5))
        b.putDouble(field(r, 9.81 + r.nextGaussian() * 2.0))
        repeat(3) { b.putDouble(field(r, r.nextGaussian() * 0.5)) }
    }

    /** 56-byte GNSS fix: t, lat, lon, alt, h. accuracy, speed, speed accuracy (NaN = null). */
    private fun fixRecord(r: Random, b: ByteBuffer, t: Double) {
        b.putDouble(t)
        b.putDouble(field(r, 50.29 + r.nextDouble() * 1e-3))
        b.putDouble(field(r, 18.67 + r.nextDouble() * 1e-3))
        repeat(4) { k ->
            val normal = doubleArrayOf(250.0, 4.0, 2.5, 0.3)[k]
            b.putDouble(if (r.nextInt(5) == 0) Double.NaN else field(r, normal * (0.5 + r.nextDouble())))
        }
    }

    /** 16-byte step count: t, u64 cumulative steps. */
    private fun stepCountRecord(r: Random, b: ByteBuffer, t: Double) {
        b.putDouble(t)
        val steps = when (r.nextInt(12)) {
            0 -> 0L
            1 -> -1L // u64::MAX
            2 -> Long.MAX_VALUE
            3 -> Long.MIN_VALUE // 2^63
            4 -> r.nextLong()
            5 -> r.nextInt(10).toLong() // a counter reset
            else -> if (t.isFinite() && t > 0 && t < 1e11) (t * 2.5).toLong() else r.nextInt(1000).toLong()
        }
        b.putLong(steps)
    }

    // ------------------------------------------------------------------------------
    // The harness
    // ------------------------------------------------------------------------------

    /** What one packed call returned: rejected record indices (null: only a count is reported), values to check. */
    private class Pushed(val records: Int, val rejected: List<Int>?, val internalRejections: List<String>, val values: List<Any?>)

    /** One packed entry point. */
    private class Entry(
        val name: String,
        val recordBytes: Int,
        val clock: StreamClock,
        val record: (Random, ByteBuffer, Double) -> Unit,
        val push: (ByteArray, Random) -> Pushed,
    )

    /** One object under test (or a stateless function): its typed error and entry points. */
    private class Target(
        val name: String,
        val typed: Class<out Throwable>,
        val internal: Class<out Throwable>,
        val invalidBuffer: Class<out Throwable>,
        val entries: List<Entry>,
        val callsPerThread: Int,
        /** Other calls mixed in (estimate, snapshot, restore): return a value to check. */
        val extras: List<Pair<String, () -> Any?>> = emptyList(),
    )

    private fun hex(b: ByteArray, max: Int = 4096): String {
        val sb = StringBuilder()
        for (i in 0 until minOf(b.size, max)) sb.append("%02x".format(b[i]))
        if (b.size > max) sb.append("…(${b.size} bytes)")
        return sb.toString()
    }

    private fun buffer(r: Random, e: Entry): ByteArray {
        val rec = e.recordBytes
        fun wellFormed(n: Int): ByteArray {
            val b = ByteBuffer.allocate(n * rec).order(ByteOrder.LITTLE_ENDIAN)
            repeat(n) { e.record(r, b, time(r, e.clock)) }
            return b.array()
        }
        val p = r.nextInt(100)
        return when {
            // (a) fully random bytes, random length (mostly not a whole number of records)
            p < 22 -> ByteArray(r.nextInt(rec * 6 + rec)).also { r.nextBytes(it) }
            // random bytes, a whole number of records: decoded as records
            p < 32 -> ByteArray(rec * r.nextInt(13)).also { r.nextBytes(it) }
            // well-formed records truncated or extended by 1..rec-1 bytes
            p < 42 -> {
                val w = wellFormed(1 + r.nextInt(16))
                val d = 1 + r.nextInt(rec - 1)
                if (r.nextBoolean()) w.copyOf(w.size - d) else w.copyOf(w.size + d)
            }
            // well-formed records with a few random bytes changed
            p < 50 -> wellFormed(1 + r.nextInt(16)).also { w ->
                repeat(1 + r.nextInt(4)) { w[r.nextInt(w.size)] = r.nextInt(256).toByte() }
            }
            // (b) well-formed records (0 records included)
            else -> wellFormed(r.nextInt(33))
        }
    }

    private fun nonFinite(v: Any?, path: String, out: MutableList<String>) {
        when (v) {
            null, is String, is Boolean, is Enum<*>, is ByteArray, is Throwable -> {}
            is Double -> if (!v.isFinite()) out += "$path = $v"
            is Float -> if (!v.isFinite()) out += "$path = $v"
            is Number -> {}
            is Collection<*> -> v.forEachIndexed { i, x -> nonFinite(x, "$path[$i]", out) }
            else -> if (v.javaClass.name.startsWith("io.stridekit.")) {
                for (f in v.javaClass.declaredFields) {
                    if (Modifier.isStatic(f.modifiers) || f.isSynthetic) continue
                    f.isAccessible = true
                    nonFinite(f.get(v), "$path.${f.name}", out)
                }
            }
        }
    }

    private fun assertFinite(v: Any?, what: String) {
        val bad = mutableListOf<String>().also { nonFinite(v, what, it) }
        assertTrue(bad.isEmpty(), "non-finite values: ${bad.take(10)}")
    }

    /** Runs the 8 threads on `t`; prints and returns every problem found. */
    private fun stress(t: Target): List<String> {
        val failures = ConcurrentLinkedQueue<String>()
        val calls = AtomicInteger()
        val thrown = AtomicInteger()
        val acceptedRecords = AtomicInteger()
        val start = CountDownLatch(1)
        val pool = Executors.newFixedThreadPool(THREADS)
        val began = System.nanoTime()
        repeat(THREADS) { k ->
            pool.execute {
                val seed = SEED + t.name.hashCode() * 31L + k
                val r = Random(seed)
                start.await()
                for (i in 0 until t.callsPerThread) {
                    val where = "${t.name} thread $k (Random($seed)) call $i"
                    if (t.extras.isNotEmpty() && r.nextInt(16) == 0) {
                        val (name, call) = t.extras[r.nextInt(t.extras.size)]
                        try {
                            val bad = mutableListOf<String>().also { nonFinite(call(), name, it) }
                            if (bad.isNotEmpty()) failures += "$where: $name(): non-finite ${bad.take(5)}"
                        } catch (e: Throwable) {
                            failures += "$where: $name() threw ${e.javaClass.name}: $e\n${e.stackTraceToString().lines().take(6).joinToString("\n")}"
                        }
                        continue
                    }
                    val e = t.entries[r.nextInt(t.entries.size)]
                    val buf = buffer(r, e)
                    val whole = buf.size % e.recordBytes == 0
                    val call = "$where: ${e.name}(${buf.size} bytes${if (whole) ", ${buf.size / e.recordBytes} records" else ""})"
                    calls.incrementAndGet()
                    try {
                        val p = e.push(buf, r)
                        if (!whole) failures += "$call returned (CONTRACT: not a whole number of ${e.recordBytes}-byte records, expected InvalidBuffer)\n  bytes ${hex(buf)}"
                        p.rejected?.let { rej ->
                            val out = rej.filter { it < 0 || it >= p.records }
                            if (out.isNotEmpty() || rej.toSet().size != rej.size) failures += "$call: rejected indices out of range or repeated: ${rej.take(20)}"
                            val rejSet = rej.toSet()
                            val bb = ByteBuffer.wrap(buf).order(ByteOrder.LITTLE_ENDIAN)
                            for (j in 0 until p.records) if (j !in rejSet) {
                                e.clock.accepted(bb.getDouble(j * e.recordBytes))
                                acceptedRecords.incrementAndGet()
                            }
                        }
                        if (p.internalRejections.isNotEmpty()) failures += "$call: records rejected as Internal (a caught panic): ${p.internalRejections.take(3)}\n  bytes ${hex(buf)}"
                        val bad = mutableListOf<String>().also { nonFinite(p.values, "result", it) }
                        if (bad.isNotEmpty()) failures += "$call: non-finite estimate values ${bad.take(5)}\n  bytes ${hex(buf)}"
                    } catch (x: Throwable) {
                        thrown.incrementAndGet()
                        when {
                            t.internal.isInstance(x) -> failures += "$call threw ${x.javaClass.name} (Internal: a caught panic): $x\n  bytes ${hex(buf)}"
                            !t.typed.isInstance(x) -> failures += "$call threw untyped ${x.javaClass.name}: $x\n  bytes ${hex(buf)}\n${x.stackTraceToString().lines().take(8).joinToString("\n")}"
                            whole -> failures += "$call threw ${x.javaClass.name} for a whole buffer (CONTRACT): $x\n  bytes ${hex(buf)}"
                            !t.invalidBuffer.isInstance(x) -> failures += "$call threw ${x.javaClass.name}, expected InvalidBuffer (CONTRACT): $x"
                        }
                    }
                }
            }
        }
        start.countDown()
        pool.shutdown()
        assertTrue(pool.awaitTermination(120, TimeUnit.SECONDS), "${t.name}: threads finished")
        val ms = (System.nanoTime() - began) / 1_000_000
        println("StressTest ${t.name}: ${calls.get()} packed calls in $ms ms, ${thrown.get()} threw (typed), ${acceptedRecords.get()} records accepted, ${failures.size} failures")
        failures.take(20).forEach { println("StressTest FAILURE: $it") }
        return failures.toList()
    }

    /**
     * Runs the usability checks even when the stress found problems (so that both are
     * reported), then fails with the stress problems and/or the usability failure.
     */
    private fun afterStress(name: String, failures: List<String>, usable: () -> Unit) {
        val unusable = runCatching(usable).exceptionOrNull()
        if (failures.isEmpty() && unusable == null) return
        val msg = buildString {
            if (failures.isNotEmpty()) append("$name: ${failures.size} failures during the stress, first: ${failures.first().lines().first()}")
            if (unusable != null) append(if (isEmpty()) "" else "; ").append("$name not usable after the stress: $unusable")
        }
        throw AssertionError(msg, unusable)
    }

    // ------------------------------------------------------------------------------
    // Valid data for the usability checks
    // ------------------------------------------------------------------------------

    /** Realistic phone IMU at 100 Hz, gravity on z, a walking bounce; mag present. */
    private fun validImu(t0: Double, n: Int, dt: Double = 0.01): ByteArray {
        val b = ByteBuffer.allocate(n * 80).order(ByteOrder.LITTLE_ENDIAN)
        for (i in 0 until n) {
            val t = t0 + i * dt
            val w = 2 * PI * 1.8 * (i * dt)
            b.putDouble(t)
            b.putDouble(0.3 * sin(w)).putDouble(0.2 * cos(w)).putDouble(9.81 + 1.5 * sin(w))
            b.putDouble(0.02 * sin(w)).putDouble(0.01 * cos(w)).putDouble(0.005)
            b.putDouble(20.0).putDouble(0.5).putDouble(-40.0)
        }
        return b.array()
    }

    private fun validAccel(t0: Double, n: Int, dt: Double = 0.01): ByteArray {
        val b = ByteBuffer.allocate(n * 32).order(ByteOrder.LITTLE_ENDIAN)
        for (i in 0 until n) {
            val w = 2 * PI * 1.8 * (i * dt)
            b.putDouble(t0 + i * dt).putDouble(0.3 * sin(w)).putDouble(0.2 * cos(w)).putDouble(9.81 + 2.0 * sin(w))
        }
        return b.array()
    }

    /** A foot at rest on a level floor (as FootTest), at the navigator's rate. */
    private fun validFoot(t0: Double, n: Int, dt: Double): ByteArray {
        val b = ByteBuffer.allocate(n * 56).order(ByteOrder.LITTLE_ENDIAN)
        for (i in 0 until n) {
            b.putDouble(t0 + i * dt).putDouble(0.02).putDouble(-0.01).putDouble(9.81)
            b.putDouble(0.001).putDouble(-0.002).putDouble(0.0005)
        }
        return b.array()
    }

    private fun validFixes(t0: Double, n: Int): ByteArray {
        val b = ByteBuffer.allocate(n * 56).order(ByteOrder.LITTLE_ENDIAN)
        for (i in 0 until n) {
            b.putDouble(t0 + i).putDouble(50.2945 + i * 1.2e-5).putDouble(18.6714)
            b.putDouble(250.0).putDouble(4.0).putDouble(1.3).putDouble(0.3)
        }
        return b.array()
    }

    private fun validStepCounts(t0: Double, n: Int, first: Long): ByteArray {
        val b = ByteBuffer.allocate(n * 16).order(ByteOrder.LITTLE_ENDIAN)
        for (i in 0 until n) b.putDouble(t0 + i).putLong(first + 2L * i)
        return b.array()
    }

    /** The time the final sequence of a stream starts at: just after its last accepted sample. */
    private fun after(c: StreamClock, dt: Double): Double {
        val last = c.maxAccepted()
        assertTrue(last.isFinite(), "the warm-up sample was accepted")
        assertTrue(last < 1e11 - 1e4, "last accepted time $last leaves room for a valid sequence")
        return last + dt
    }

    private fun <T> assertNoRejections(rejected: List<T>, what: String) =
        assertTrue(rejected.isEmpty(), "$what: valid samples rejected after the stress: ${rejected.take(3)}")

    // ------------------------------------------------------------------------------
    // The objects
    // ------------------------------------------------------------------------------

    /**
     * Found three bugs, fixed in the core (regression: core/tests/robustness.rs
     * `sparse_step_counts_give_a_human_cadence_and_a_restorable_session`): step counts a
     * few seconds apart after a pause gave 638 steps/min from 12 steps in 5 s, a step
     * stream behind the fix stream moved the reference cadence by a negative time, and
     * a prediction across a long gap grew the covariance past what a snapshot holds —
     * each left a live tracker whose own snapshot `restore` refused.
     */
    @Test
    fun `PaceTracker packed fixes, step counts and accelerometer`() {
        PaceTracker.withDefaults().use { o ->
            val gnss = StreamClock(T0, 1.0)
            val steps = StreamClock(T0, 0.5)
            val accel = StreamClock(T0, 0.01)
            // Warm-up: anchor every stream at T0.
            assertNoRejections(o.pushFixesPacked(validFixes(T0, 1)).rejected, "warm-up fix")
            assertNoRejections(o.pushStepCountsPacked(validStepCounts(T0, 1, 0)).rejected, "warm-up steps")
            assertNoRejections(o.pushAccelPacked(validAccel(T0, 1)).rejected, "warm-up accel")
            listOf(gnss, steps, accel).forEach { it.accepted(T0) }

            fun pushed(n: Int, r: io.stridekit.BatchResult) = Pushed(
                n, r.rejected.map { it.index.toInt() },
                r.rejected.filter { it.error is PaceException.Internal }.map { it.reason },
                listOf(r.estimates, r.latest),
            )
            val failures = stress(
                Target(
                    "PaceTracker", PaceException::class.java, PaceException.Internal::class.java, PaceException.InvalidBuffer::class.java,
                    listOf(
                        Entry("pushFixesPacked", 56, gnss, ::fixRecord) { b, _ -> pushed(b.size / 56, o.pushFixesPacked(b)) },
                        Entry("pushStepCountsPacked", 16, steps, ::stepCountRecord) { b, _ -> pushed(b.size / 16, o.pushStepCountsPacked(b)) },
                        Entry("pushAccelPacked", 32, accel, ::accelRecord) { b, _ -> pushed(b.size / 32, o.pushAccelPacked(b)) },
                    ),
                    callsPerThread = 360,
                    extras = listOf(
                        "estimate" to { o.estimate() },
                        "detectedSteps" to { o.detectedSteps() },
                        "snapshot+restore" to { PaceTracker.restore(o.snapshot()).use { it.estimate() } },
                    ),
                ),
            )
            afterStress("PaceTracker", failures) {
                // Still usable: valid data of every stream after its last accepted sample.
                // Detected steps (from the accelerometer) also feed the step stream.
                val tAccel = after(accel, 0.01)
                val tSteps = maxOf(after(steps, 1.0), tAccel + 1.0)
                val tFix = after(gnss, 1.0)
                val ra = o.pushAccelPacked(validAccel(tAccel, 300))
                assertNoRejections(ra.rejected, "accelerometer")
                val rs = o.pushStepCountsPacked(validStepCounts(maxOf(tSteps, tAccel + 301 * 0.01), 10, 0))
                assertNoRejections(rs.rejected, "step counts")
                val rf = o.pushFixesPacked(validFixes(tFix, 15))
                assertNoRejections(rf.rejected, "fixes")
                assertEquals(15, rf.estimates.size)
                assertFinite(listOf(ra.latest, rs.latest, rf.estimates, rf.latest, o.estimate()), "PaceTracker estimate")

                val saved = o.snapshot()
                PaceTracker.restore(saved).use { c ->
                    assertContentEquals(saved, c.snapshot())
                    assertEquals(o.estimate(), c.estimate())
                    val more = validFixes(tFix + 15, 5)
                    assertEquals(o.pushFixesPacked(more), c.pushFixesPacked(more), "the restored tracker continues identically")
                }
            }
        }
    }

    @Test
    fun `PhoneNavigator packed IMU`() {
        PhoneNavigator.withDefaults().use { o ->
            val imu = StreamClock(T0, 0.01)
            assertNoRejections(o.pushImuPacked(validImu(T0, 1)).rejected, "warm-up")
            imu.accepted(T0)
            val failures = stress(
                Target(
                    "PhoneNavigator", NavException::class.java, NavException.Internal::class.java, NavException.InvalidBuffer::class.java,
                    listOf(
                        Entry("pushImuPacked", 80, imu, ::imuRecord) { b, _ ->
                            val r = o.pushImuPacked(b)
                            Pushed(b.size / 80, r.rejected.map { it.index.toInt() }, r.rejected.map { it.reason }.filter { it.startsWith("internal error") }, listOf(r.steps, r.latest))
                        },
                    ),
                    callsPerThread = 300,
                    extras = listOf(
                        "estimate" to { o.estimate() },
                        "snapshot+restore" to { PhoneNavigator.restore(o.snapshot()).use { it.estimate() } },
                    ),
                ),
            )
            afterStress("PhoneNavigator", failures) {
                val t = after(imu, 0.01)
                val r = o.pushImuPacked(validImu(t, 300))
                assertNoRejections(r.rejected, "IMU")
                assertFinite(listOf(r.steps, r.latest, o.estimate()), "PhoneNavigator estimate")

                val saved = o.snapshot()
                PhoneNavigator.restore(saved).use { c ->
                    assertContentEquals(saved, c.snapshot())
                    assertEquals(o.estimate(), c.estimate())
                    val more = validImu(t + 3.0, 200)
                    assertEquals(o.pushImuPacked(more), c.pushImuPacked(more), "the restored navigator continues identically")
                }
            }
        }
    }

    @Test
    fun `PhoneOdometry packed IMU`() {
        PhoneOdometry.withDefaults().use { o ->
            val imu = StreamClock(T0, 0.01)
            assertNoRejections(o.pushImuPacked(validImu(T0, 1)).rejected, "warm-up")
            imu.accepted(T0)
            val failures = stress(
                Target(
                    "PhoneOdometry", OdometryException::class.java, OdometryException.Internal::class.java, OdometryException.InvalidBuffer::class.java,
                    listOf(
                        Entry("pushImuPacked", 80, imu, ::imuRecord) { b, _ ->
                            val r = o.pushImuPacked(b)
                            Pushed(b.size / 80, r.rejected.map { it.index.toInt() }, r.rejected.map { it.reason }.filter { it.startsWith("internal error") }, listOf(r.latest))
                        },
                    ),
                    callsPerThread = 250,
                    extras = listOf(
                        "estimate" to { o.estimate() },
                        "placementEstimate" to { o.placementEstimate() },
                        "snapshot+restore" to { PhoneOdometry.restore(o.snapshot()).use { it.estimate() } },
                    ),
                ),
            )
            afterStress("PhoneOdometry", failures) {
                val t = after(imu, 0.01)
                val r = o.pushImuPacked(validImu(t, 400))
                assertNoRejections(r.rejected, "IMU")
                assertFinite(listOf(r.latest, o.estimate(), o.placementEstimate()), "PhoneOdometry estimate")

                val saved = o.snapshot()
                PhoneOdometry.restore(saved).use { c ->
                    assertContentEquals(saved, c.snapshot())
                    assertEquals(o.estimate(), c.estimate())
                    val more = validImu(t + 4.0, 300)
                    assertEquals(o.pushImuPacked(more), c.pushImuPacked(more), "the restored odometry continues identically")
                }
            }
        }
    }

    @Test
    fun `OrientationFilter packed IMU`() {
        OrientationFilter.withDefaults().use { o ->
            val imu = StreamClock(T0, 0.01)
            assertNoRejections(o.pushImuPacked(validImu(T0, 1), OrientationOutput.ALL).rejected, "warm-up")
            imu.accepted(T0)
            val outputs = OrientationOutput.entries
            val failures = stress(
                Target(
                    "OrientationFilter", OrientationException::class.java, OrientationException.Internal::class.java, OrientationException.InvalidBuffer::class.java,
                    listOf(
                        Entry("pushImuPacked", 80, imu, ::imuRecord) { b, r ->
                            val res = o.pushImuPacked(b, outputs[r.nextInt(outputs.size)])
                            Pushed(b.size / 80, res.rejected.map { it.index.toInt() }, res.rejected.map { it.reason }.filter { it.startsWith("internal error") }, listOf(res.estimates, res.latest))
                        },
                    ),
                    callsPerThread = 300,
                    extras = listOf(
                        "estimate" to { o.estimate() },
                        "snapshot+restore" to { OrientationFilter.restore(o.snapshot()).use { it.estimate() } },
                    ),
                ),
            )
            afterStress("OrientationFilter", failures) {
                val t = after(imu, 0.01)
                val r = o.pushImuPacked(validImu(t, 300), OrientationOutput.ALL)
                assertNoRejections(r.rejected, "IMU")
                assertEquals(300, r.accepted)
                assertFinite(listOf(r.estimates, r.latest, o.estimate()), "OrientationFilter estimate")

                val saved = o.snapshot()
                OrientationFilter.restore(saved).use { c ->
                    assertContentEquals(saved, c.snapshot())
                    assertEquals(o.estimate(), c.estimate())
                    val more = validImu(t + 3.0, 200)
                    assertEquals(o.pushImuPacked(more, OrientationOutput.ALL), c.pushImuPacked(more, OrientationOutput.ALL), "the restored filter continues identically")
                }
            }
        }
    }

    @Test
    fun `PlacementClassifier packed accelerometer`() {
        PlacementClassifier.withDefaults().use { o ->
            val accel = StreamClock(T0, 0.01)
            assertNoRejections(o.pushAccelPacked(validAccel(T0, 1)).rejected, "warm-up")
            accel.accepted(T0)
            val failures = stress(
                Target(
                    "PlacementClassifier", PlacementException::class.java, PlacementException.Internal::class.java, PlacementException.InvalidBuffer::class.java,
                    listOf(
                        Entry("pushAccelPacked", 32, accel, ::accelRecord) { b, _ ->
                            val r = o.pushAccelPacked(b)
                            Pushed(b.size / 32, r.rejected.map { it.index.toInt() }, r.rejected.map { it.reason }.filter { it.startsWith("internal error") }, listOf(r.latest))
                        },
                    ),
                    callsPerThread = 300,
                    extras = listOf(
                        "estimate" to { o.estimate() },
                        "snapshot+restore" to { PlacementClassifier.restore(o.snapshot()).use { it.estimate() } },
                    ),
                ),
            )
            afterStress("PlacementClassifier", failures) {
                val t = after(accel, 0.01)
                // 12 s: well over one 5.12 s window.
                val r = o.pushAccelPacked(validAccel(t, 1200))
                assertNoRejections(r.rejected, "accelerometer")
                assertTrue(r.produced > 0, "windows classified after the stress")
                assertFinite(listOf(r.latest, o.estimate()), "PlacementClassifier estimate")

                val saved = o.snapshot()
                PlacementClassifier.restore(saved).use { c ->
                    assertContentEquals(saved, c.snapshot())
                    assertEquals(o.estimate(), c.estimate())
                    val more = validAccel(t + 12.0, 600)
                    assertEquals(o.pushAccelPacked(more), c.pushAccelPacked(more), "the restored classifier continues identically")
                }
            }
        }
    }

    @Test
    fun `FootNavigator packed IMU`() {
        FootNavigator.withDefaults().use { o ->
            // sampleRateHz() is 0 until the alignment measured it: push 200 Hz (as FootTest).
            val dt = 0.005
            val foot = StreamClock(T0, dt)
            assertNoRejections(o.pushPacked(validFoot(T0, 1, dt), FootOutput.ALL).rejected.map { it.reason }, "warm-up")
            foot.accepted(T0)
            val outputs = FootOutput.entries
            val failures = stress(
                Target(
                    "FootNavigator", FootException::class.java, FootException.Internal::class.java, FootException.InvalidBuffer::class.java,
                    listOf(
                        Entry("pushPacked", 56, foot, ::footRecord) { b, r ->
                            val res = o.pushPacked(b, outputs[r.nextInt(outputs.size)])
                            Pushed(
                                b.size / 56, res.rejected.map { it.index.toInt() },
                                res.rejected.filter { it.error is FootException.Internal }.map { it.reason },
                                listOf(res.estimates, res.latest),
                            )
                        },
                    ),
                    callsPerThread = 300,
                    extras = listOf(
                        "estimate" to { o.estimate() },
                        "isAligned" to { o.isAligned() },
                        "snapshot+restore" to { FootNavigator.restore(o.snapshot()).use { it.estimate() } },
                    ),
                ),
            )
            afterStress("FootNavigator", failures) {
                val t = after(foot, dt)
                val n = (3.0 / dt).toInt()
                val r = o.pushPacked(validFoot(t, n, dt), FootOutput.ALL)
                assertNoRejections(r.rejected, "foot IMU")
                assertFinite(listOf(r.estimates, r.latest, o.estimate()), "FootNavigator estimate")

                val saved = o.snapshot()
                FootNavigator.restore(saved).use { c ->
                    assertContentEquals(saved, c.snapshot())
                    assertEquals(o.estimate(), c.estimate())
                    val more = validFoot(t + n * dt, n, dt)
                    assertEquals(o.pushPacked(more, FootOutput.ALL), c.pushPacked(more, FootOutput.ALL), "the restored navigator continues identically")
                }
            }
        }
    }

    @Test
    fun `pdrReferenceReplay packed IMU`() {
        // Stateless: every call replays its buffer into a fresh navigator.
        val imu = StreamClock(0.0, 0.01)
        val failures = stress(
            Target(
                "pdrReferenceReplay", NavException::class.java, NavException.Internal::class.java, NavException.InvalidBuffer::class.java,
                listOf(
                    Entry("pdrReferenceReplay", 80, imu, ::imuRecord) { b, _ ->
                        val r = pdrReferenceReplay(b, null)
                        Pushed(b.size / 80, null, emptyList(), listOf(r.steps, r.latest))
                    },
                ),
                callsPerThread = 100,
            ),
        )
        afterStress("pdrReferenceReplay", failures) {
            val r = pdrReferenceReplay(validImu(0.0, 300), null)
            assertEquals(0, r.rejected)
            assertFinite(listOf(r.steps, r.latest), "replay")
        }
    }
}
