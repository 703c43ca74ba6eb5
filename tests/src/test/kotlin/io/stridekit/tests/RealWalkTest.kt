package io.stridekit.tests

import io.stridekit.NavException
import io.stridekit.PhoneNavigator
import io.stridekit.pdrCalibrationFromText
import io.stridekit.pdrCalibrationToText
import io.stridekit.pdrReferenceReplay
import org.junit.jupiter.api.Assumptions.assumeTrue
import java.io.File
import java.nio.ByteBuffer
import java.nio.ByteOrder
import java.util.zip.GZIPInputStream
import kotlin.math.hypot
import kotlin.test.Test
import kotlin.test.assertContentEquals
import kotlin.test.assertEquals
import kotlin.test.assertFailsWith
import kotlin.test.assertNotNull
import kotlin.test.assertTrue

/**
 * One real indoor walk (an Android sensor log of `../shared/data/phone-indoor`, read here
 * in Kotlin as an app that logged it would) through `PhoneNavigator` in packed batches
 * of 1 000 samples with a personal calibration loaded: exactly the trajectory of the
 * Rust replay of the same samples (`pdrReferenceReplay`: the core navigator fed one by
 * one in Rust). Skipped when the data is absent.
 */
class RealWalkTest {
    private val walk = "site1/F1/5dd9e7aac5b77e0006b1732b.txt.gz"

    /** A calibration as `stridekit calibrate pdr` writes it (values of an example user). */
    private val calibrationText = """
        stridekit-pdr-calibration 1
        # example: pendulum K for one user, phone held in front (top edge forward)
        step_length pendulum 2.8 0 0 sigma 0.028 1 1
        carrying 0.08 0.996 0.0
    """.trimIndent()

    private fun dataDir(): File? =
        (System.getenv("STRIDEKIT_DATA") ?: System.getProperty("stridekit.data"))?.let { File(it, "phone-indoor") }

    /**
     * The log's IMU samples as 80-byte records (t, accel xyz, gyro xyz, mag xyz), built as
     * the Rust reader does: at the accelerometer's times, gyroscope and magnetometer
     * interpolated linearly between their events around it (held 0.1 s past the ends).
     */
    private fun packedImu(file: File): ByteArray {
        val acc = ArrayList<DoubleArray>()
        val gyr = ArrayList<DoubleArray>()
        val mag = ArrayList<DoubleArray>()
        GZIPInputStream(file.inputStream()).bufferedReader().useLines { lines ->
            for (line in lines) {
                if (line.isBlank() || line.startsWith("#")) continue
                val f = line.trim().split(Regex("\\s+"))
                val stream = when (f[1]) {
                    "TYPE_ACCELEROMETER" -> acc
                    "TYPE_GYROSCOPE" -> gyr
                    "TYPE_MAGNETIC_FIELD" -> mag
                    else -> continue
                }
                stream.add(doubleArrayOf(f[0].toDouble() / 1000.0, f[2].toDouble(), f[3].toDouble(), f[4].toDouble()))
            }
        }
        gyr.sortBy { it[0] }
        mag.sortBy { it[0] }
        fun at(s: List<DoubleArray>, t: Double): DoubleArray? {
            if (s.isEmpty()) return null
            var i = s.indexOfLast { it[0] <= t }
            if (i < 0) return if (s[0][0] - t <= 0.1) s[0].copyOfRange(1, 4) else null
            val a = s[i]
            val b = s.getOrNull(i + 1)
            if (b == null || b[0] <= a[0]) return if (t - a[0] <= 0.1) a.copyOfRange(1, 4) else null
            val k = (t - a[0]) / (b[0] - a[0])
            return DoubleArray(3) { a[it + 1] + k * (b[it + 1] - a[it + 1]) }
        }
        val out = ByteBuffer.allocate(acc.size * 80).order(ByteOrder.LITTLE_ENDIAN)
        var n = 0
        for (a in acc) {
            val g = at(gyr, a[0]) ?: continue
            val m = at(mag, a[0]) ?: doubleArrayOf(Double.NaN, Double.NaN, Double.NaN)
            out.putDouble(a[0])
            for (j in 1..3) out.putDouble(a[j])
            g.forEach { out.putDouble(it) }
            m.forEach { out.putDouble(it) }
            n++
        }
        return out.array().copyOf(n * 80)
    }

    @Test
    fun `a real walk in batches with a calibration is exactly the Rust replay`() {
        val file = dataDir()?.let { File(it, walk) }
        assumeTrue(file?.isFile == true, "skipping: ../shared/data/phone-indoor not found (set STRIDEKIT_DATA)")
        val packed = packedImu(file!!)
        val calibration = pdrCalibrationFromText(calibrationText)
        val reference = pdrReferenceReplay(packed, calibration)
        PhoneNavigator.withCalibration(calibration).use { nav ->
            assertEquals(calibration, nav.calibration())
            val steps = ArrayList<io.stridekit.NavStep>()
            var rejected = 0
            for (start in packed.indices step 1000 * 80) {
                val r = nav.pushImuPacked(packed.copyOfRange(start, minOf(packed.size, start + 1000 * 80)))
                rejected += r.rejected.size
                steps.addAll(r.steps)
            }
            assertEquals(reference.rejected.toInt(), rejected)
            assertEquals(reference.steps, steps, "the trajectory through the FFI is the Rust one, bit for bit")
            assertEquals(reference.latest, nav.estimate())
            val last = steps.last()
            println(
                "RealWalkTest: ${packed.size / 80} samples, ${steps.size} steps, ${"%.1f".format(assertNotNull(nav.estimate()).distanceM)} m, " +
                    "end ${"%.1f".format(hypot(last.eastM, last.northM))} m from the start",
            )
            assertTrue(steps.size > 20, "a 31 s walk has steps: ${steps.size}")
            // The calibration travels with the snapshot.
            PhoneNavigator.restore(nav.snapshot()).use { again ->
                assertEquals(calibration, again.calibration())
                assertContentEquals(nav.snapshot(), again.snapshot())
            }
        }
    }

    @Test
    fun `calibration text round trips and bad ones are typed errors`() {
        val c = pdrCalibrationFromText(calibrationText)
        assertEquals(c, pdrCalibrationFromText(pdrCalibrationToText(c)))
        assertNotNull(c.carryingBody)
        assertFailsWith<NavException.InvalidCalibration> { pdrCalibrationFromText("stridekit-pdr-calibration 2\n") }
        assertFailsWith<NavException.InvalidCalibration> { pdrCalibrationFromText(calibrationText.replace("pendulum 2.8", "pendulum NaN")) }
        assertFailsWith<NavException.InvalidCalibration> { PhoneNavigator.withCalibration(c.copy(stepLengthTheta = listOf(1.0))) }
        PhoneNavigator.withDefaults().use { nav ->
            val before = nav.snapshot()
            assertFailsWith<NavException.InvalidCalibration> { nav.setCalibration(c.copy(stepLengthSigma = listOf(0.0, 1.0, 1.0))) }
            assertContentEquals(before, nav.snapshot())
            nav.setCalibration(c)
            assertEquals(c, nav.calibration())
        }
    }
}
