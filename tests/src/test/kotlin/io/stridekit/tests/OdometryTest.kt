package io.stridekit.tests

import io.stridekit.OdometryException
import io.stridekit.OdometryPlacementSource
import io.stridekit.PhoneOdometry
import io.stridekit.PhonePlacement
import io.stridekit.odometryConfigDefault
import io.stridekit.odometryShippedModel
import io.stridekit.simulatePhoneWalk
import org.junit.jupiter.api.Test
import java.util.concurrent.CountDownLatch
import java.util.concurrent.Executors
import java.util.concurrent.TimeUnit
import java.util.concurrent.atomic.AtomicInteger
import kotlin.math.hypot
import kotlin.test.assertContentEquals
import kotlin.test.assertEquals
import kotlin.test.assertFailsWith
import kotlin.test.assertNotNull
import kotlin.test.assertNull
import kotlin.test.assertTrue

/** Learned phone odometry from Kotlin: simulated walks packed, identical to Rust, errors, snapshots, threads. */
class OdometryTest {
    private val record = 80

    private fun chunks(packed: ByteArray, records: Int): List<ByteArray> =
        (0 until packed.size step records * record).map { packed.copyOfRange(it, minOf(packed.size, it + records * record)) }

    @Test
    fun `a simulated walk pushed in batches equals the Rust reference and moves like the truth`() {
        val walk = simulatePhoneWalk(seed = 21uL, placement = PhonePlacement.IN_HAND, speedMps = 1.3, durationS = 90.0)
        PhoneOdometry.withDefaults().use { o ->
            assertNull(o.estimate())
            var estimates = 0
            for (c in chunks(walk.imuPacked, 1000)) {
                val r = o.pushImuPacked(c)
                assertTrue(r.rejected.isEmpty(), "rejected: ${r.rejected.take(3)}")
                estimates += r.produced
            }
            val e = assertNotNull(o.estimate())
            assertEquals(walk.referenceFinal, e, "the FFI gives what Rust computes")
            assertTrue(estimates > 500, "estimates $estimates")
            // The default source is the general regressor (docs/odometry-pipeline.md).
            assertEquals(OdometryPlacementSource.Unknown, o.config().placement)
            assertNull(e.regressorPlacement)
            val n = walk.truthEastM.size - 1
            val straight = hypot(walk.truthEastM[n] - walk.truthEastM[0], walk.truthNorthM[n] - walk.truthNorthM[0])
            val travelled = hypot(e.eastM, e.northM)
            println("OdometryTest: 90 s in hand: end ${"%.1f".format(travelled)} m from the start (truth ${"%.1f".format(straight)} m, walked ${"%.1f".format(walk.truthDistanceM)} m)")
            // The shipped model is trained on real hand-held walks: on this simulated
            // walk its distance is within 10 % but its direction does not carry over
            // (docs/odometry.md, `eval odometry`), so the check is the distance from the
            // start; a broken pipeline is off by the whole walk.
            assertTrue(
                kotlin.math.abs(travelled - straight) < 0.3 * walk.truthDistanceM,
                "end $travelled m from the start, truth $straight m, walked ${walk.truthDistanceM} m",
            )
        }
    }

    @Test
    fun `placement sources, snapshots and the shipped model`() {
        val walk = simulatePhoneWalk(seed = 22uL, placement = PhonePlacement.ARMBAND, speedMps = 1.1, durationS = 30.0)
        val half = (walk.samples.toInt() / 2) * record
        PhoneOdometry(odometryConfigDefault().copy(placement = OdometryPlacementSource.Auto)).use { o ->
            o.pushImuPacked(walk.imuPacked.copyOfRange(0, half))
            val saved = o.snapshot()
            PhoneOdometry.restore(saved).use { resumed ->
                o.pushImuPacked(walk.imuPacked.copyOfRange(half, walk.imuPacked.size))
                resumed.pushImuPacked(walk.imuPacked.copyOfRange(half, walk.imuPacked.size))
                assertEquals(o.estimate(), resumed.estimate())
                assertContentEquals(o.snapshot(), resumed.snapshot())
            }
            val p = assertNotNull(o.placementEstimate(), "Auto runs the classifier")
            assertEquals(p.placement, o.estimate()?.detectedPlacement)
            o.setPlacement(OdometryPlacementSource.Fixed(PhonePlacement.ARMBAND))
            assertEquals(OdometryPlacementSource.Fixed(PhonePlacement.ARMBAND), o.config().placement)
        }
        PhoneOdometry.withModel(odometryConfigDefault(), odometryShippedModel()).use { assertNull(it.estimate()) }
    }

    @Test
    fun `bad input is a typed error or reported by index`() {
        PhoneOdometry.withDefaults().use { o ->
            assertFailsWith<OdometryException.InvalidBuffer> { o.pushImuPacked(ByteArray(79)) }
            val one = simulatePhoneWalk(1uL, PhonePlacement.BAG, 1.0, 2.0).imuPacked.copyOfRange(0, 2 * record)
            java.nio.ByteBuffer.wrap(one).order(java.nio.ByteOrder.LITTLE_ENDIAN).putDouble(record + 8, Double.NaN)
            val r = o.pushImuPacked(one)
            assertEquals(listOf(1), r.rejected.map { it.index })
        }
        assertFailsWith<OdometryException.InvalidModel> { PhoneOdometry.withModel(odometryConfigDefault(), "stridekit-odometry 1\n") }
        assertFailsWith<OdometryException.InvalidSnapshot> { PhoneOdometry.restore(byteArrayOf(9, 9, 9)) }
        assertFailsWith<OdometryException.InvalidConfig> { simulatePhoneWalk(1uL, PhonePlacement.BAG, 99.0, 2.0) }
    }

    @Test
    fun `four threads pushing into one engine do not crash or lose samples`() {
        val walk = simulatePhoneWalk(seed = 23uL, placement = PhonePlacement.POCKET, speedMps = 1.4, durationS = 40.0)
        val parts = chunks(walk.imuPacked, 200)
        val next = AtomicInteger(0)
        val rejected = AtomicInteger(0)
        val failures = AtomicInteger(0)
        val start = CountDownLatch(1)
        val pool = Executors.newFixedThreadPool(4)
        PhoneOdometry.withDefaults().use { o ->
            repeat(4) {
                pool.submit {
                    start.await()
                    while (true) {
                        // Each thread takes the next chunk and pushes it; the lock inside
                        // serialises the pushes, chunks may arrive out of order.
                        val k = next.getAndIncrement()
                        if (k >= parts.size) break
                        try {
                            rejected.addAndGet(o.pushImuPacked(parts[k]).rejected.size)
                            o.estimate()
                        } catch (e: Throwable) {
                            failures.incrementAndGet()
                        }
                    }
                }
            }
            start.countDown()
            pool.shutdown()
            assertTrue(pool.awaitTermination(60, TimeUnit.SECONDS))
            assertEquals(0, failures.get())
            // Out-of-order chunks: their samples are rejected as not increasing in time,
            // never crash; whatever was accepted gives finite output.
            assertTrue(rejected.get() < walk.samples.toInt())
            o.estimate()?.let { assertTrue(it.eastM.isFinite() && it.northM.isFinite()) }
        }
    }
}
