// Box3D's side of `cargo run --release --example column`: a column of unit boxes (density
// 100, friction 0.6) on a floor, sleeping off, dt 1/60; prints the top box's displacement
// every 100 steps in the same form. Build against a Box3D checkout built with cmake
// (`cmake -DCMAKE_BUILD_TYPE=Release -DBOX3D_SAMPLES=OFF -DBOX3D_UNIT_TESTS=OFF ..; make box3d`):
//   cc -O2 -I$BOX3D/include peer/box3d/column.c $BOX3D/build/src/libbox3d.a -lm -lpthread -o column
//   ./column BOXES SUBSTEPS STEPS [HERTZ]
#include "box3d/box3d.h"
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

int main( int argc, char** argv )
{
	int boxes = argc > 1 ? atoi( argv[1] ) : 25;
	int substeps = argc > 2 ? atoi( argv[2] ) : 4;
	int steps = argc > 3 ? atoi( argv[3] ) : 600;

	b3WorldDef worldDef = b3DefaultWorldDef();
	worldDef.gravity = ( b3Vec3 ){ 0.0f, -9.81f, 0.0f };
	worldDef.enableSleep = false;
	b3WorldId world = b3CreateWorld( &worldDef );
	if ( argc > 4 )
	{
		b3World_SetContactTuning( world, (float)atof( argv[4] ), 10.0f, 3.0f );
	}

	b3BodyDef floorDef = b3DefaultBodyDef();
	floorDef.position = ( b3Pos ){ 0.0f, -1.0f, 0.0f };
	b3BodyId floor = b3CreateBody( world, &floorDef );
	b3BoxHull floorHull = b3MakeBoxHull( 50.0f, 1.0f, 50.0f );
	b3ShapeDef shapeDef = b3DefaultShapeDef();
	b3CreateHullShape( floor, &shapeDef, &floorHull.base );

	b3BodyDef bodyDef = b3DefaultBodyDef();
	bodyDef.type = b3_dynamicBody;
	shapeDef.density = 100.0f;
	b3BoxHull hull = b3MakeBoxHull( 0.5f, 0.5f, 0.5f );
	b3BodyId top = b3_nullBodyId;
	float startY = 0.0f;
	for ( int k = 0; k < boxes; ++k )
	{
		startY = 0.5f * ( 2 * k + 1 );
		bodyDef.position = ( b3Pos ){ 0.0f, startY, 0.0f };
		top = b3CreateBody( world, &bodyDef );
		b3CreateHullShape( top, &shapeDef, &hull.base );
	}

	printf( "%d boxes, %d substeps: the top box's displacement (mm)\n", boxes, substeps );
	for ( int step = 1; step <= steps; ++step )
	{
		b3World_Step( world, 1.0f / 60.0f, substeps );
		if ( step % 100 == 0 )
		{
			b3Pos p = b3Body_GetPosition( top );
			printf( "step %5d: sideways %9.2f, down %8.2f\n", step, 1e3f * sqrtf( p.x * p.x + p.z * p.z ),
					1e3f * ( startY - p.y ) );
		}
	}
	b3DestroyWorld( world );
	return 0;
}
