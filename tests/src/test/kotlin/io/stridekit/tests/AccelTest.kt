package io.stridekit.tests

import io.stridekit.AccelSample
import io.stridekit.PaceException
import io.stridekit.PaceTracker
import org.junit.jupiter.api.Assumptions.assumeTrue
import org.junit.jupiter.api.Test
import java.io.File
import java.nio.ByteBuffer
import java.nio.ByteOrder
import kotlin.math.abs
import kotlin.test.assertContentEquals
import kotlin.test.assertEquals
import kotlin.test.assertFailsWith
import kotlin.test.assertTrue

/** Raw accelerometer input from Kotlin: real phone traces, packed and as records. */
class AccelTest {
    private fun dataDir(): File? =
        (System.getenv("STRIDEKIT_DATA") ?: System.getProperty("stridekit.data"))
            ?.let { File(it) }
            ?.takeIf { it.isDirectory }

    @Test
    fun `a real Oxford trace pushed packed gives the reference step count`() {
        val trace = dataDir()?.resolve("steps/oxford/Samsung_Carmelo_Hard_BackPocket_1")
        assumeTrue(trace?.isDirectory == true, "skipping: ../shared/data not found (set STRIDEKIT_DATA)")
        // accelerometer.csv: timestamp ns, accuracy, ax, ay, az (m/s²); no header.
        val rows = trace!!.resolve("accelerometer.csv").readLines().mapNotNull { line ->
            val f = line.split(',')
            if (f.size < 5) null else listOf(f[0].trim().toDouble() / 1e9, f[2].toDouble(), f[3].toDouble(), f[4].toDouble())
        }
        // stepcounter.csv: timestamp ns, foot 1, foot 2; each 0→1 transition is a step.
        var reference = 0
        var prev = intArrayOf(0, 0)
        trace.resolve("stepcounter.csv").readLines().forEach { line ->
            val f = line.split(',').map { it.trim() }
            if (f.size >= 3) {
                val now = intArrayOf(f[1].toInt(), f[2].toInt())
                for (k in 0..1) if (prev[k] == 0 && now[k] == 1) reference++
                prev = now
            }
        }
        val buf = ByteBuffer.allocate(rows.size * 32).order(ByteOrder.LITTLE_ENDIAN)
        var last = Double.NEGATIVE_INFINITY
        var packed = 0
        for (r in rows) {
            if (r[0] <= last) continue // the reader drops non-increasing timestamps too
            last = r[0]
            r.forEach { buf.putDouble(it) }
            packed++
        }
        PaceTracker.withDefaults().use { t ->
            val result = t.pushAccelPacked(buf.array().copyOf(packed * 32))
            assertTrue(result.rejected.isEmpty(), "rejected: ${result.rejected.take(3)}")
            val detected = t.detectedSteps().toDouble()
            val err = (detected - reference) / reference
            assertTrue(abs(err) < 0.03, "detected $detected vs reference $reference")
            assertTrue((t.estimate()!!.cadenceSpm ?: 0.0) >= 0.0)
        }
    }

    @Test
    fun `accelerations in g are a typed error and change nothing`() {
        PaceTracker.withDefaults().use { t ->
            val before = t.snapshot()
            val r = t.pushAccelSamples(listOf(AccelSample(tS = 0.0, xMps2 = 0.0, yMps2 = 0.0, zMps2 = 1.0)))
            assertEquals(1, r.rejected.size)
            assertTrue(r.rejected[0].error is PaceException.AccelerationNotInMps2, "${r.rejected[0].error}")
            assertContentEquals(before, t.snapshot())
            assertFailsWith<PaceException.InvalidBuffer> { t.pushAccelPacked(ByteArray(31)) }
        }
    }
}
