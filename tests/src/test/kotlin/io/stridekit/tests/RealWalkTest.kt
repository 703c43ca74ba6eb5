package io.stridekit.tests

import io.stridekit.NavException
import io.stridekit.PhoneNavigator
import io.stridekit.pdrCalibrationFromText
import io.stridekit.pdrCalibrationToText
import io.stridekit.pdrReferenceReplay
import org.junit.jupiter.api.Assumptions.assumeTrue
import java.io.File
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

    @Test
    fun `a real walk in batches with a calibration is exactly the Rust replay`() {
        val file = AndroidLog.dataDir()?.let { File(it, walk) }
        assumeTrue(file?.isFile == true, "skipping: ../shared/data/phone-indoor not found (set STRIDEKIT_DATA)")
        val packed = AndroidLog.read(file!!).packedImu
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
