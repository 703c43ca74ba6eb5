package io.stridekit.tests

import io.stridekit.FixPosition
import io.stridekit.FloorPlan
import io.stridekit.MapEstimate
import io.stridekit.MapException
import io.stridekit.MapFix
import io.stridekit.MapNavigator
import io.stridekit.PlanPoint
import io.stridekit.SmoothedPoint
import io.stridekit.mapConfigDefault
import io.stridekit.mapReferenceReplay
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
 * One real indoor walk on its floor plan, read in Kotlin as an app would: the plan from
 * its GeoJSON text, the log's IMU samples packed in batches, two fixes in latitude and
 * longitude made from its waypoints. Exactly the Rust replay of the same inputs
 * (`mapReferenceReplay`: the core engine fed one by one): every estimate, the smoothed
 * path, the snapshot. Skipped when the data is absent.
 */
class MapWalkTest {
    private val floor = "site1/F1"
    private val walk = "$floor/5dd9e7aac5b77e0006b1732b.txt.gz"

    @Test
    fun `a real walk on its plan through the FFI is exactly the Rust track`() {
        val dir = AndroidLog.dataDir()?.let { File(it, floor) }
        val log = AndroidLog.dataDir()?.let { File(it, walk) }
        assumeTrue(log?.isFile == true && dir?.isDirectory == true, "skipping: ../shared/data/phone-indoor not found (set STRIDEKIT_DATA)")
        val plan = FloorPlan.fromCompetitionGeojson(File(dir, "geojson_map.json").readText(), File(dir, "floor_info.json").readText())
        assertEquals(1, plan.floor())
        val androidLog = AndroidLog.read(log!!)
        val packed = androidLog.packedImu
        val wp = androidLog.waypoints
        val start = PlanPoint(wp[0][1], wp[0][2])
        assertTrue(plan.isWalkable(start.xM, start.yM))
        // Two fixes from waypoints, 3 m off, in latitude/longitude through the plan's reference.
        val fixes = listOf(2, 4).map { k ->
            val ll = assertNotNull(plan.toLatLon(PlanPoint(wp[k][1] + 3.0, wp[k][2])))
            MapFix(tS = wp[k][0], position = FixPosition.LatLon(ll.latDeg, ll.lonDeg), accuracyM = 4.5, floor = 1)
        }
        val reference = mapReferenceReplay(packed, listOf(plan), start, 1.0, fixes)
        val samples = packed.size / 80
        MapNavigator.withDefaults(listOf(plan)).use { nav ->
            assertEquals(mapConfigDefault(), nav.config())
            nav.startAt(start.xM, start.yM, 1.0, null)
            val path = ArrayList<SmoothedPoint>()
            val latest = ArrayList<MapEstimate>()
            var rejected = 0
            var accepted = 0
            var i = 0
            var fi = 0
            while (i < samples) {
                // Batches of up to 1 000 samples, cut where a fix comes in.
                while (fi < fixes.size && fixes[fi].tS <= AndroidLog.timeOf(packed, i)) nav.pushFix(fixes[fi++])
                var end = minOf(samples, i + 1000)
                if (fi < fixes.size) {
                    val cut = (i until end).firstOrNull { AndroidLog.timeOf(packed, it) >= fixes[fi].tS }
                    if (cut != null && cut > i) end = cut
                }
                val r = nav.pushImuPacked(packed.copyOfRange(i * 80, end * 80))
                rejected += r.rejected.size
                accepted += r.accepted
                path.addAll(r.smoothedFixed)
                r.latest?.let { latest.add(it) }
                assertEquals(reference.estimates[accepted - 1], r.latest, "the estimate after sample ${end - 1}")
                i = end
            }
            path.addAll(nav.smoothedWindow())
            assertEquals(reference.rejected, rejected)
            assertEquals(reference.estimates.last(), nav.estimate())
            assertEquals(reference.smoothed, path, "the smoothed path through the FFI is the Rust one")
            assertContentEquals(reference.snapshot, nav.snapshot())
            val e = assertNotNull(nav.estimate())
            assertEquals(2L, e.fixesUsed + e.fixesRejected)
            assertEquals(1, e.floor)
            val last = wp.last()
            println(
                "MapWalkTest: $samples samples, ${e.steps} steps, ${path.size} smoothed points, " +
                    "end ${"%.1f".format(hypot(e.xM - last[1], e.yM - last[2]))} m from the last waypoint",
            )
            // The snapshot resumes over the same plan only.
            MapNavigator.restore(nav.snapshot(), listOf(plan)).use { again ->
                assertContentEquals(nav.snapshot(), again.snapshot())
            }
            assertFailsWith<MapException.InvalidSnapshot> { MapNavigator.restore(nav.snapshot(), listOf()) }
        }
    }

    @Test
    fun `bad plans, starts and fixes are typed errors`() {
        assertFailsWith<MapException.InvalidPlan> { FloorPlan.fromGeojson("{}", null, null) }
        assertFailsWith<MapException.InvalidPlan> { FloorPlan.fromCompetitionGeojson("""{"type": "FeatureCollection", "features": []}""", "{}") }
        val hall = """{"type": "FeatureCollection", "features": [{"type": "Feature", "properties": {"floor_num": 2},
            "geometry": {"type": "Polygon", "coordinates": [[[8.0, 47.0], [8.0004, 47.0], [8.0004, 47.0002], [8.0, 47.0002], [8.0, 47.0]]]}}]}"""
        val plan = FloorPlan.fromGeojson(hall, null, null)
        assertEquals(2, plan.floor())
        assertTrue(plan.walkableAreaM2() > 600.0)
        MapNavigator.withDefaults(listOf(plan)).use { nav ->
            nav.startAt(10.0, 10.0, null, null)
            val before = nav.snapshot()
            assertFailsWith<MapException.OffPlan> { nav.startAt(500.0, 10.0, null, null) }
            assertFailsWith<MapException.Floor> { nav.setFloor(3) }
            assertFailsWith<MapException.NonFinite> { nav.pushFix(MapFix(1.0, FixPosition.Plan(Double.NaN, 1.0), 3.0, null)) }
            assertFailsWith<MapException.OutOfRange> { nav.pushFix(MapFix(1.0, FixPosition.Plan(1.0, 1.0), -3.0, null)) }
            assertFailsWith<MapException.InvalidBuffer> { nav.pushImuPacked(ByteArray(79)) }
            assertContentEquals(before, nav.snapshot(), "refusals change nothing")
        }
        assertFailsWith<MapException.InvalidConfig> { MapNavigator(mapConfigDefault().copy(particles = 2), listOf(plan)) }
        assertFailsWith<MapException.Floor> { MapNavigator.withDefaults(listOf(plan, plan)) }
    }
}
