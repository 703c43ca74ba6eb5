package io.stridekit.tests

import io.stridekit.AccelSample
import io.stridekit.PhonePlacement
import io.stridekit.PlacementClassifier
import io.stridekit.PlacementException
import io.stridekit.phonePlacements
import io.stridekit.placementShippedModel
import org.junit.jupiter.api.Assumptions.assumeTrue
import org.junit.jupiter.api.Test
import java.io.File
import java.nio.ByteBuffer
import java.nio.ByteOrder
import kotlin.math.abs
import kotlin.test.assertContentEquals
import kotlin.test.assertEquals
import kotlin.test.assertFailsWith
import kotlin.test.assertNotNull
import kotlin.test.assertNull
import kotlin.test.assertTrue

/** The placement classifier from Kotlin: a real Oxford trace packed, records, errors, snapshots. */
class PlacementTest {
    private fun dataDir(): File? =
        (System.getenv("STRIDEKIT_DATA") ?: System.getProperty("stridekit.data"))
            ?.let { File(it) }
            ?.takeIf { it.isDirectory }

    /** accelerometer.csv of an Oxford trace packed as 32-byte records (t s, ax, ay, az m/s²). */
    private fun packedTrace(trace: File): ByteArray {
        val rows = trace.resolve("accelerometer.csv").readLines().mapNotNull { line ->
            val f = line.split(',')
            if (f.size < 5) null else doubleArrayOf(f[0].trim().toDouble() / 1e9, f[2].toDouble(), f[3].toDouble(), f[4].toDouble())
        }
        val buf = ByteBuffer.allocate(rows.size * 32).order(ByteOrder.LITTLE_ENDIAN)
        var last = Double.NEGATIVE_INFINITY
        var n = 0
        for (r in rows) {
            if (r[0] <= last) continue
            last = r[0]
            r.forEach { buf.putDouble(it) }
            n++
        }
        return buf.array().copyOf(n * 32)
    }

    @Test
    fun `a real trouser-pocket trace pushed packed is classified as a pocket`() {
        val trace = dataDir()?.resolve("steps/oxford/Samsung_Carmelo_Hard_FrontPocket_1")
        assumeTrue(trace?.isDirectory == true, "skipping: ../shared/data not found (set STRIDEKIT_DATA)")
        PlacementClassifier.withDefaults().use { c ->
            assertNull(c.estimate())
            val r = c.pushAccelPacked(packedTrace(trace!!))
            assertTrue(r.rejected.isEmpty(), "rejected: ${r.rejected.take(3)}")
            assertTrue(r.produced > 50, "windows ${r.produced}")
            val e = assertNotNull(r.latest)
            println("PlacementTest: ${trace.name}: ${e.placement} (confidence ${"%.2f".format(e.confidence)}) after ${e.windows} windows")
            // The shipped model has seen this trace in training: this checks the
            // pipeline across the FFI, not accuracy (docs/odometry.md has the
            // leave-one-user-out figures).
            assertEquals(PhonePlacement.POCKET, e.placement)
            assertEquals(phonePlacements().size, e.probabilities.size)
            assertEquals(1.0, e.probabilities.sum(), 1e-9)
        }
    }

    @Test
    fun `records and packed pushes agree and snapshots resume exactly`() {
        val samples = (0 until 1500).map { i ->
            val t = i / 100.0
            val a = kotlin.math.sin(2 * Math.PI * 1.8 * t)
            AccelSample(tS = t, xMps2 = 0.4 * a, yMps2 = 9.8 + 2.5 * a, zMps2 = 0.2 * a)
        }
        val buf = ByteBuffer.allocate(samples.size * 32).order(ByteOrder.LITTLE_ENDIAN)
        samples.forEach { s -> listOf(s.tS, s.xMps2, s.yMps2, s.zMps2).forEach { buf.putDouble(it) } }
        PlacementClassifier.withDefaults().use { a ->
            PlacementClassifier.withDefaults().use { b ->
                a.pushAccelSamples(samples.take(700))
                val saved = a.snapshot()
                PlacementClassifier.restore(saved).use { resumed ->
                    resumed.pushAccelSamples(samples.drop(700))
                    a.pushAccelSamples(samples.drop(700))
                    b.pushAccelPacked(buf.array())
                    assertEquals(a.estimate(), b.estimate())
                    assertEquals(a.estimate(), resumed.estimate())
                    assertContentEquals(a.snapshot(), resumed.snapshot())
                    val e = assertNotNull(a.estimate())
                    assertTrue(e.confidence > 0.0 && abs(e.probabilities.sum() - 1.0) < 1e-9)
                }
            }
        }
    }

    @Test
    fun `bad input is a typed error or reported by index`() {
        PlacementClassifier.withDefaults().use { c ->
            val before = c.snapshot()
            val r = c.pushAccelSamples(listOf(
                AccelSample(tS = 0.0, xMps2 = Double.NaN, yMps2 = 0.0, zMps2 = 9.8),
                AccelSample(tS = 0.01, xMps2 = 0.0, yMps2 = 0.0, zMps2 = 9.8),
                AccelSample(tS = 0.005, xMps2 = 0.0, yMps2 = 0.0, zMps2 = 9.8),
            ))
            assertEquals(listOf(0, 2), r.rejected.map { it.index })
            assertTrue(r.rejected.all { it.reason.isNotEmpty() })
            assertTrue(!before.contentEquals(c.snapshot()), "the good sample was taken")
            assertFailsWith<PlacementException.InvalidBuffer> { c.pushAccelPacked(ByteArray(33)) }
        }
        assertFailsWith<PlacementException.InvalidModel> { PlacementClassifier.withModel("not a model", 8) }
        assertFailsWith<PlacementException.InvalidSnapshot> { PlacementClassifier.restore(byteArrayOf(1, 2, 3)) }
        PlacementClassifier.withModel(placementShippedModel(), 8).use { assertNull(it.estimate()) }
    }
}
