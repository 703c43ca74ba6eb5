package io.stridekit.tests

import io.stridekit.OrientationAlgorithm
import io.stridekit.OrientationEstimate
import io.stridekit.OrientationException
import io.stridekit.OrientationFilter
import io.stridekit.OrientationFrame
import io.stridekit.OrientationOutput
import io.stridekit.OrientationSettings
import io.stridekit.orientationSettingsDefault
import java.io.File
import java.nio.ByteBuffer
import java.nio.ByteOrder
import java.util.zip.GZIPInputStream
import kotlin.math.abs
import kotlin.math.acos
import kotlin.math.atan2
import kotlin.math.min
import kotlin.math.sqrt
import kotlin.test.Test
import kotlin.test.assertContentEquals
import kotlin.test.assertEquals
import kotlin.test.assertFailsWith
import kotlin.test.assertNotNull
import kotlin.test.assertTrue

/** OrientationFilter from Kotlin: a real BROAD trial in packed batches, settings, errors, snapshot. */
class OrientationTest {
    private fun dataDir(): File? =
        (System.getenv("STRIDEKIT_DATA") ?: System.getProperty("stridekit.data"))
            ?.let { File(it) }
            ?.takeIf { it.isDirectory }

    /** A BROAD trial: the 80-byte records (t, accel xyz, gyro xyz, mag xyz), the optical truth (null: occluded), movement. */
    private class Trial(val packed: ByteArray, val truth: List<DoubleArray?>, val movement: List<Boolean>) {
        val size get() = truth.size
    }

    private fun broadTrial(name: String): Trial? {
        val file = dataDir()?.resolve("orientation/broad/$name.csv.gz")?.takeIf { it.isFile } ?: return null
        val lines = GZIPInputStream(file.inputStream()).bufferedReader().readLines()
        val cols = lines.first().split(',').map { it.trim() }
        fun col(n: String) = cols.indexOf(n).also { assertTrue(it >= 0, "column $n missing") }
        val imu = listOf("t_s", "acc_x_mps2", "acc_y_mps2", "acc_z_mps2", "gyr_x_rads", "gyr_y_rads", "gyr_z_rads",
            "mag_x_ut", "mag_y_ut", "mag_z_ut").map(::col)
        val opt = listOf("opt_qw", "opt_qx", "opt_qy", "opt_qz").map(::col)
        val mov = col("movement")
        val rows = lines.drop(1).filter { it.isNotBlank() }
        val buf = ByteBuffer.allocate(rows.size * 80).order(ByteOrder.LITTLE_ENDIAN)
        val truth = ArrayList<DoubleArray?>(rows.size)
        val movement = ArrayList<Boolean>(rows.size)
        for (line in rows) {
            val f = line.split(',')
            for (i in imu) buf.putDouble(f[i].trim().toDoubleOrNull() ?: Double.NaN)
            val q = opt.map { f[it].trim().toDoubleOrNull() }
            truth.add(if (q.all { it != null }) DoubleArray(4) { q[it]!! } else null)
            movement.add(f[mov].trim() == "1")
        }
        return Trial(buf.array(), truth, movement)
    }

    /** BROAD's metric: RMSE during movement of the total / heading / inclination error of q_est ⊗ q_truth⁻¹, degrees. */
    private fun broadErrors(est: List<OrientationEstimate>, trial: Trial): Triple<Double, Double, Double> {
        var (t2, h2, i2, n) = listOf(0.0, 0.0, 0.0, 0.0)
        for (k in est.indices) {
            val truth = trial.truth[k] ?: continue
            if (!trial.movement[k]) continue
            val a = est[k].quaternion
            val b = doubleArrayOf(truth[0], -truth[1], -truth[2], -truth[3])
            val nb = sqrt(b.sumOf { it * it })
            val w = (a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3]) / nb
            val z = (a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0]) / nb
            val total = 2 * acos(min(abs(w), 1.0))
            val heading = 2 * atan2(abs(z), abs(w))
            val incl = 2 * acos(min(sqrt(w * w + z * z), 1.0))
            t2 += total * total; h2 += heading * heading; i2 += incl * incl; n += 1.0
        }
        fun deg(s: Double) = Math.toDegrees(sqrt(s / n))
        return Triple(deg(t2), deg(h2), deg(i2))
    }

    @Test
    fun `a BROAD trial in packed batches gives the Rust numbers exactly and resumes from a snapshot`() {
        val trial = broadTrial("01_undisturbed_slow_rotation_A") ?: run {
            println("OrientationTest: ../shared/data/orientation/broad not found (set STRIDEKIT_DATA): skipping the real trial")
            return
        }
        // Rust's own replay: the whole trial in one native call.
        val reference = OrientationFilter.withDefaults().use { f ->
            val r = f.pushImuPacked(trial.packed, OrientationOutput.ALL)
            assertTrue(r.rejected.isEmpty(), "${r.rejected.take(3)}")
            assertEquals(trial.size, r.accepted)
            r.estimates
        }
        // The app's way: batches of 1000 records, a snapshot and restore in the middle.
        val got = ArrayList<OrientationEstimate>(trial.size)
        val recordBytes = 80
        val batches = (0 until trial.size step 1000).map { it * recordBytes to min(trial.size, it + 1000) * recordBytes }
        var filter = OrientationFilter.withDefaults()
        for ((k, range) in batches.withIndex()) {
            val r = filter.pushImuPacked(trial.packed.copyOfRange(range.first, range.second), OrientationOutput.ALL)
            assertTrue(r.rejected.isEmpty())
            assertEquals(r.estimates.last(), r.latest)
            got += r.estimates
            if (k == batches.size / 2) {
                val saved = filter.snapshot()
                filter.close()
                filter = OrientationFilter.restore(saved)
                assertContentEquals(saved, filter.snapshot())
            }
        }
        assertEquals(reference.size, got.size)
        for (i in reference.indices) {
            if (reference[i] != got[i]) throw AssertionError("estimate $i differs:\n  Rust  ${reference[i]}\n  batch ${got[i]}")
        }
        assertEquals(reference.last(), filter.estimate())
        filter.close()

        val (total, heading, incl) = broadErrors(got, trial)
        println("OrientationTest: BROAD trial 01, default filter: RMSE total %.2f°, heading %.2f°, inclination %.2f° (docs/orientation.md)".format(total, heading, incl))
        // `stridekit eval orientation` reports 2.05 / 1.96 / 0.61 for this trial; the
        // bounds catch a broken pipeline, not a change of the last digit.
        assertTrue(total < 3.0 && incl < 1.0, "total $total°, inclination $incl°")
        val last = reference.last()
        assertTrue(last.flags.atRest, "the trial ends at rest")
        assertEquals(4, last.quaternion.size)
        assertEquals(9.80665, sqrt(last.gravityBodyMps2.sumOf { it * it }), 1e-9)
    }

    @Test
    fun `settings defaults agree with the core, errors are typed, bad records are skipped`() {
        assertEquals(orientationSettingsDefault(), OrientationSettings(algorithm = OrientationAlgorithm.DECOUPLED, frame = OrientationFrame.ENU),
            "literal defaults = the core's")
        val d = orientationSettingsDefault()
        assertEquals(OrientationAlgorithm.DECOUPLED, d.algorithm)
        assertEquals(OrientationFrame.ENU, d.frame)
        assertFailsWith<OrientationException.InvalidSettings> { OrientationFilter(d.copy(accelTimeConstantS = -1.0)) }
        assertFailsWith<OrientationException.InvalidSnapshot> { OrientationFilter.restore(byteArrayOf(1, 2, 3)) }
        OrientationFilter(d.copy(algorithm = OrientationAlgorithm.MADGWICK, madgwickGain = 0.12)).use { f ->
            assertEquals(OrientationAlgorithm.MADGWICK, f.settings().algorithm)
            assertEquals(0.12, f.settings().madgwickGain)
        }
        OrientationFilter.withDefaults().use { f ->
            assertFailsWith<OrientationException.InvalidBuffer> { f.pushImuPacked(ByteArray(81), OrientationOutput.LATEST_ONLY) }
            val n = 300
            val buf = ByteBuffer.allocate(n * 80).order(ByteOrder.LITTLE_ENDIAN)
            for (i in 0 until n) {
                val gx = if (i == 7) Double.NaN else 0.001
                listOf(i / 100.0, 0.0, 0.0, 9.81, gx, 0.0, 0.0, 20.0, 0.0, -40.0).forEach { buf.putDouble(it) }
            }
            val r = f.pushImuPacked(buf.array(), OrientationOutput.LATEST_ONLY)
            assertEquals(listOf(7), r.rejected.map { it.index })
            assertEquals((n - 1), r.accepted)
            assertTrue(r.estimates.isEmpty())
            val e = assertNotNull(r.latest)
            assertTrue(abs(e.gravityBodyMps2[2] - 9.80665) < 0.01, "level: ${e.gravityBodyMps2}")
            // A sample at the same time as the previous one: typed, state unchanged.
            val before = f.snapshot()
            assertFailsWith<OrientationException.TimeNotIncreasing> { f.push((n - 1) / 100.0, listOf(0.0, 0.0, 0.0), listOf(0.0, 0.0, 9.81), null) }
            assertFailsWith<OrientationException.InvalidSample> { f.push(10.0, listOf(0.0, 0.0), listOf(0.0, 0.0, 9.81), null) }
            assertContentEquals(before, f.snapshot())
            val one = f.push(10.0, listOf(0.0, 0.0, 0.0), listOf(0.0, 0.0, 9.81), listOf(20.0, 0.0, -40.0))
            assertEquals(10.0, one.tS)
        }
    }
}
